#ifndef FREESTAND_TESTS_POST_CHROMIUM_SCREENSHOT_H
#define FREESTAND_TESTS_POST_CHROMIUM_SCREENSHOT_H

// Reports as a browser shows them: headless Chromium renders an HTML file to
// a PNG, read back with VTK; plot frames are found by their colour and the
// pixels inside them checked for the colours of the data.

#include <filesystem>
#include <string>
#include <vector>

namespace freestand::test {

// True when Debian's `chromium` is on the PATH (scripts/setup.sh installs it).
bool chromium_installed();

// Renders `html` at width x height CSS pixels into `png`; Chromium's output
// goes to work_dir/chromium.log, its private profile to work_dir/profile.
// Returns an empty string on success, else what went wrong.
std::string chromium_screenshot(const std::filesystem::path& html, const std::filesystem::path& png,
                                const std::filesystem::path& work_dir, int width, int height);

struct Rgb {
  double r, g, b;
};
Rgb parse_colour(const std::string& hex);  // "#RRGGBB"

class Screenshot {
 public:
  explicit Screenshot(const std::filesystem::path& png);
  int width() const { return width_; }
  int height() const { return height_; }
  const Rgb& at(int x, int y) const { return pixels_[std::size_t(y) * width_ + x]; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<Rgb> pixels_;
};

inline constexpr Rgb kWhite{255, 255, 255};

// Pixel drawn in `c` on `background`, allowing for anti-aliasing: it lies on
// the background-to-c line at least 60 % of the way to c, within 30 levels of it.
bool shows(const Rgb& p, const Rgb& c, const Rgb& background = kWhite);
bool near(const Rgb& p, const Rgb& c, double tolerance);

struct Box {
  int left, top, right, bottom;  // frame pixels, inclusive
};

// Plot frames, top to bottom: horizontal runs of the frame colour at least
// 200 px long, paired top and bottom by their extent (only frames are drawn
// in that colour).
std::vector<Box> find_frames(const Screenshot& shot);

// Fraction of the 20-pixel-wide slices of the frame, between data x values
// [from, to] of an axis running from 0 at the left edge to `span` at the
// right, that show colour c. Slices, not single columns: where two lines
// cross, the one drawn last hides the other for a few columns.
double slices_showing(const Screenshot& shot, const Box& box, const Rgb& c, double from, double to, double span);

// Pixels inside the frame, between data x values [from, to] (as above), showing c
// on `background`.
int pixels_showing(const Screenshot& shot, const Box& box, const Rgb& c, double from = 0, double to = 1,
                   double span = 1, const Rgb& background = kWhite);

}  // namespace freestand::test

#endif
