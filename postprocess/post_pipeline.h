#ifndef FREESTAND_POST_POST_PIPELINE_H
#define FREESTAND_POST_POST_PIPELINE_H

// `freestand post`: everything made from a results file, written next to it:
// the channels in the recording format (channels.csv + channels.nominal.json),
// the ParaView series (paraview/), and a per-body summary on the terminal.

#include <string>

namespace freestand {

struct PostOptions {
  bool csv = true;          // channels.csv + channels.nominal.json
  bool vtk = true;          // paraview/*.pvd, *.vtp
  double vtk_rate = 25.0;   // ParaView frames per simulated second (the last sample always)
};

void postprocess(const std::string& results_path, const PostOptions& options);

}  // namespace freestand

#endif
