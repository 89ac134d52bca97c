#ifndef FREESTAND_POST_PROGRESS_H
#define FREESTAND_POST_PROGRESS_H

// A progress bar with elapsed time and ETA for long runs, on standard error:
// redrawn in place on a terminal, a line every 10 % otherwise (logs, CI).

#include <chrono>
#include <string>

namespace freestand {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  // `done` of `total` units of work.
  void update(long done, long total);
  // Ends the bar's line.
  void finish();

 private:
  std::string label_;                                  // what is being done
  std::chrono::steady_clock::time_point start_;        // when the bar was made
  bool terminal_;                                      // stderr is a terminal
  int last_decile_ = -1;                               // last 10 % step printed (not a terminal)
  double last_draw_ = -1.0;                            // seconds since start of the last redraw
};

// "1 h 02 min", "3 min 20 s", "12 s".
std::string format_duration(double seconds);

}  // namespace freestand

#endif
