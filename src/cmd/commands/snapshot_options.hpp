// The drawing options of `snapshot write` and `snapshot every`: declared once, read and checked
// in the check phase into SnapOptions, independent of the renderer's types, so the build
// without the renderer parses and checks exactly the same calls.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "cmd/commands/commands.hpp"

namespace demlab::cmd {

using Colour = std::array<float, 3>;

struct SnapOptions {
  int width = 800, height = 600;
  std::string colourBy;           // a field name, or "" with fixed set
  std::optional<Colour> fixed;    // -color #rrggbb or a colour name
  std::string colourMap;          // "" : by field (categorical for id, material, tag)
  std::vector<std::string> tags;  // -tags: the tags drawn (and with -color tag the categories)
  std::vector<double> values;     // -color value: one per element
  std::string valueUnit;          // -unit: their unit, for the legend
  std::optional<std::array<double, 2>> range;  // -range {lo hi}
  bool rangeFirst = false;  // -range first: fixed at the first frame with a spread of values
  bool cameraFixed = false;  // -camera fixed: the first frame's framing kept (series only)
  bool camera = false;       // any of position, lookat, up given
  sim::Vec3d position{0, -10, 0}, lookAt{}, up{0, 0, 1};
  double fov = 30, viewHeight = 0;
  bool ortho = false;
  Colour background{1, 1, 1};
  int antialias = 2;
  bool legend = true, timeStamp = true;
  std::string title;
  int quality = 90;   // JPEG quality
  bool jpeg = false;  // the format of the file(s) written
  bool chains = false;
  double chainMin = 1;                         // chains drawn above this fraction of the mean
  std::optional<std::array<double, 6>> clip;   // {px py pz nx ny nz}, the normal unit length
  bool walls = true;
  std::vector<std::int64_t> highlight;  // script ids of elements drawn in the highlight colour
};

// Returns nothing; declares the drawing options every drawing subcommand takes. series: the
// command writes a series (`snapshot every`), which has -camera and other defaults. Changes c.
void drawingOptions(Command& c, bool series);

// Check phase: returns the options of the call, every one checked. now: `snapshot write`
// (a single frame now) rather than a series. Throws {VALUE <PARAM>}. Changes nothing.
SnapOptions readOptions(const Call& c, bool now);

// Check phase: returns whether the image file `param` names is a JPEG (.jpg, .jpeg) rather
// than a PNG (.png), by its extension, case-insensitive. Throws {VALUE <PARAM>} for any other.
bool isJpegName(const Call& c, std::string_view param);

// Returns the unit of a colour field ("m/s", "N", ...), "" for none.
std::string fieldUnit(const std::string& field);

}  // namespace demlab::cmd
