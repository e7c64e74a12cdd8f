#pragma once
// Limits on what input files and scripts may ask of the renderer, checked when they are read so that a
// hostile or broken input gets an InputError instead of a crash deep inside the parser or Embree.
//
// - JSON nesting: every JSON the program reads (glTF, the JSON chunk of a GLB, shot scripts) is scanned
//   before it is parsed; deeper than kMaxJsonDepth levels of [ and { is refused. The parsers recurse
//   once per level, and 100,000 levels overflow the stack. glTF and shot scripts need fewer than 10
//   levels; 512 leaves room for deep `extras` and costs under 100 KB of stack.
// - Coordinates: every world-space position (vertices after their node transforms, lights, camera) and
//   every keyframed position lies within +-kMaxCoordinate. Ray arithmetic multiplies up to three
//   coordinate differences (Embree's ray-triangle test, squared distances times a cosine): at 1e8 that
//   is (2e8)^3 = 8e24, far below FLT_MAX (3.4e38), with room left for the radiance it is multiplied by.
//   1e38 vertex positions overflowed to inf/NaN there and tripped Embree's ray-validity assertion.
// - Emission: emitted radiance (a material's emissiveFactor x strength, per channel) and punctual light
//   intensities are at most kMaxEmission. A light's power is radiance x area x 2 pi in float: 1e10 x
//   (4e16 m^2, the largest triangle within the coordinate limit) x 2 pi = 2.5e27, finite, and the
//   samplers sum powers in double. A shot script may scale emission by at most kMaxPowerScale more.
#include <string>
#include <string_view>

namespace candela {

inline constexpr int kMaxJsonDepth = 512;
inline constexpr float kMaxCoordinate = 1e8f;
inline constexpr float kMaxEmission = 1e10f;
inline constexpr float kMaxPowerScale = 1e6f;

// Scans `text` for nesting of [ and { outside strings (a backslash inside a string escapes the next
// character) and throws InputError("FILE: JSON nested deeper than N levels") past kMaxJsonDepth. Does
// not check anything else: malformed JSON is left for the parser to report.
void check_json_nesting(std::string_view text, const std::string& file);

}  // namespace candela
