#include "chromium_screenshot.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "svg_plot.h"

namespace freestand::test {

namespace fs = std::filesystem;

bool chromium_installed() { return std::system("command -v chromium > /dev/null 2>&1") == 0; }

std::string chromium_screenshot(const fs::path& html, const fs::path& png, const fs::path& work_dir, int width,
                                int height) {
  const fs::path log = work_dir / "chromium.log";
  // --headless is Chromium's new headless mode (the old one is gone since
  // Chromium 132). No sandbox: CI runs as root. A private profile keeps HOME untouched.
  const std::string command =
      "timeout 60 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
      "--force-device-scale-factor=1 --no-first-run --user-data-dir='" + (work_dir / "profile").string() +
      "' --window-size=" + std::to_string(width) + "," + std::to_string(height) + " --screenshot='" + png.string() +
      "' 'file://" + fs::absolute(html).string() + "' > '" + log.string() + "' 2>&1";
  if (std::system(command.c_str()) != 0) return "chromium failed, see " + log.string();
  if (!fs::exists(png)) return "no screenshot, see " + log.string();
  return "";
}

Rgb parse_colour(const std::string& hex) {
  const long v = std::stol(hex.substr(1), nullptr, 16);
  return {double((v >> 16) & 255), double((v >> 8) & 255), double(v & 255)};
}

Screenshot::Screenshot(const fs::path& png) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  width_ = dims[0], height_ = dims[1];
  auto* scalars = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  if (!scalars) return;
  const int components = scalars->GetNumberOfComponents();
  pixels_.resize(std::size_t(width_) * height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const unsigned char* p = scalars->GetPointer(
          (std::size_t(height_ - 1 - y) * width_ + x) * components);  // VTK rows run bottom-up
      pixels_[std::size_t(y) * width_ + x] = {double(p[0]), double(p[1]), double(p[2])};
    }
}

bool shows(const Rgb& p, const Rgb& c, const Rgb& background) {
  const double dr = c.r - background.r, dg = c.g - background.g, db = c.b - background.b;
  const double pr = p.r - background.r, pg = p.g - background.g, pb = p.b - background.b;
  const double a = (pr * dr + pg * dg + pb * db) / (dr * dr + dg * dg + db * db);
  const double er = pr - a * dr, eg = pg - a * dg, eb = pb - a * db;
  return a >= 0.6 && std::sqrt(er * er + eg * eg + eb * eb) <= 30;
}

bool near(const Rgb& p, const Rgb& c, double tolerance) {
  return std::abs(p.r - c.r) <= tolerance && std::abs(p.g - c.g) <= tolerance && std::abs(p.b - c.b) <= tolerance;
}

std::vector<Box> find_frames(const Screenshot& shot) {
  const Rgb frame = parse_colour(svg::kFrameColour);
  struct Run {
    int y, x0, x1;
  };
  std::vector<Run> runs;
  for (int y = 0; y < shot.height(); ++y)
    for (int x = 0; x < shot.width();) {
      int end = x;
      while (end < shot.width() && near(shot.at(end, y), frame, 8)) ++end;
      if (end - x >= 200) runs.push_back({y, x, end - 1});
      x = std::max(end, x + 1);
    }
  std::vector<Box> boxes;
  std::vector<bool> used(runs.size(), false);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (used[i]) continue;
    for (std::size_t j = i + 1; j < runs.size(); ++j)
      if (!used[j] && std::abs(runs[j].x0 - runs[i].x0) <= 1 && std::abs(runs[j].x1 - runs[i].x1) <= 1 &&
          runs[j].y - runs[i].y > 50) {
        boxes.push_back({runs[i].x0, runs[i].y, runs[i].x1, runs[j].y});
        used[i] = used[j] = true;
        break;
      }
  }
  return boxes;
}

double slices_showing(const Screenshot& shot, const Box& box, const Rgb& c, double from, double to, double span) {
  constexpr int kSlice = 20;
  const double width = box.right - box.left + 1;
  const int x0 = box.left + 1 + static_cast<int>(std::ceil(from / span * width));
  const int x1 = box.left - 1 + static_cast<int>(std::floor(to / span * width));
  int slices = 0, hits = 0;
  for (int start = x0; start + kSlice - 1 <= x1; start += kSlice, ++slices) {
    bool hit = false;
    for (int x = start; x < start + kSlice && !hit; ++x)
      for (int y = box.top + 1; y < box.bottom && !hit; ++y) hit = shows(shot.at(x, y), c);
    hits += hit;
  }
  return slices ? double(hits) / slices : 0;
}

int pixels_showing(const Screenshot& shot, const Box& box, const Rgb& c, double from, double to, double span,
                   const Rgb& background) {
  const double width = box.right - box.left + 1;
  const int x0 = box.left + 1 + static_cast<int>(std::ceil(from / span * width));
  const int x1 = std::min(box.right - 1, box.left - 1 + static_cast<int>(std::floor(to / span * width)));
  int hits = 0;
  for (int y = box.top + 1; y < box.bottom; ++y)
    for (int x = x0; x <= x1; ++x) hits += shows(shot.at(x, y), c, background);
  return hits;
}

}  // namespace freestand::test
