// Checks the content of what a `candela render` run wrote, for the cli.render_* tests (tests/cli_expect.sh
// runs it after the command). Checks follow one another on the command line:
//   stats FILE FRAMES STAGE,...  the --stats JSON: an array of FRAMES frames numbered 0.., each with
//                                spp >= 1, rays > 0 and non_finite 0, holding every named stage (each with
//                                non_finite 0); a name written +NAME is required from the second frame on
//                                (stages that need history: temporal reuse, the boiling filter)
//   image FILE WIDTH HEIGHT MIN  an image (PNG or EXR) of that size, not all black, whose every channel of
//                                every pixel is finite and at least MIN
//   same FILE REFERENCE          two images (PNG or EXR) of one size whose pixels hold the same bits (EXR headers
//                                carry a capture date, so the files' bytes differ where the images do not)
// Prints every problem found and exits 1 if there was any, else 0.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/check.h"
#include "engine/image.h"

namespace candela {
namespace {

int problems = 0;

void problem(const std::string& file, const std::string& what) {
  std::fprintf(stderr, "%s: %s\n", file.c_str(), what.c_str());
  ++problems;
}

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

void check_stats(const std::string& file, int frames, const std::vector<std::string>& stages) {
  if (stages.empty()) return problem(file, "no stages given to check");
  std::ifstream in(file);
  nlohmann::json json = nlohmann::json::parse(in, nullptr, false);
  if (json.is_discarded() || !json.is_array()) return problem(file, "not a JSON array");
  if (int(json.size()) != frames)
    problem(file, std::to_string(json.size()) + " frames, expected " + std::to_string(frames));
  for (size_t k = 0; k < json.size(); ++k) {
    const nlohmann::json& f = json[k];
    const std::string where = "frame " + std::to_string(k) + ": ";
    if (f.value("frame", -1) != int(k)) problem(file, where + "numbered " + f.value("frame", nlohmann::json()).dump());
    if (f.value("spp", 0) < 1) problem(file, where + "spp " + f.value("spp", nlohmann::json()).dump());
    if (f.value("rays", 0.0) <= 0.0) problem(file, where + "no rays counted");
    if (f.value("non_finite", -1) != 0)
      problem(file, where + "non_finite " + f.value("non_finite", nlohmann::json()).dump());
    for (std::string name : stages) {
      const bool needs_history = name[0] == '+';
      if (needs_history) name.erase(0, 1);
      if (needs_history && k == 0) continue;
      bool found = false;
      for (const nlohmann::json& s : f.value("stages", nlohmann::json::array()))
        if (s.value("name", "") == name) {
          found = true;
          if (s.value("non_finite", -1) != 0) problem(file, where + "stage " + name + " dropped non-finite values");
        }
      if (!found) problem(file, where + "no stage " + name);
    }
  }
}

void check_image(const std::string& file, int width, int height, float min) {
  Image image;
  try {
    image = read_image(file);
  } catch (const InputError& e) {
    return problem(file, e.what());
  }
  if (image.width != width || image.height != height)
    problem(file, std::to_string(image.width) + "x" + std::to_string(image.height) + ", expected " +
                      std::to_string(width) + "x" + std::to_string(height));
  size_t bad = 0, lit = 0;
  for (const vec3& p : image.pixels) {
    bad += !(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && p.x >= min && p.y >= min && p.z >= min);
    lit += p.x > 0.0f || p.y > 0.0f || p.z > 0.0f;
  }
  if (bad > 0) problem(file, std::to_string(bad) + " pixels not finite or below " + std::to_string(min));
  if (lit == 0) problem(file, "every pixel is black");
}

void check_same(const std::string& file, const std::string& reference) {
  Image image, expected;
  try {
    image = read_image(file);
    expected = read_image(reference);
  } catch (const InputError& e) {
    return problem(file, e.what());
  }
  if (image.width != expected.width || image.height != expected.height)
    return problem(file, std::to_string(image.width) + "x" + std::to_string(image.height) + ", but " + reference +
                             " is " + std::to_string(expected.width) + "x" + std::to_string(expected.height));
  size_t differ = 0;
  for (size_t i = 0; i < image.pixels.size(); ++i)
    differ += std::memcmp(&image.pixels[i], &expected.pixels[i], sizeof(vec3)) != 0;
  if (differ > 0) problem(file, std::to_string(differ) + " pixels differ from " + reference);
}

}  // namespace
}  // namespace candela

int main(int argc, char** argv) try {
  std::vector<std::string> args(argv + 1, argv + argc);
  for (size_t i = 0; i < args.size();) {
    if (args[i] == "stats" && i + 3 < args.size()) {
      candela::check_stats(args[i + 1], std::stoi(args[i + 2]), candela::split(args[i + 3]));
      i += 4;
    } else if (args[i] == "image" && i + 4 < args.size()) {
      candela::check_image(args[i + 1], std::stoi(args[i + 2]), std::stoi(args[i + 3]), std::stof(args[i + 4]));
      i += 5;
    } else if (args[i] == "same" && i + 2 < args.size()) {
      candela::check_same(args[i + 1], args[i + 2]);
      i += 3;
    } else {
      std::fprintf(stderr,
                   "usage: check_outputs [stats FILE FRAMES STAGE,... | image FILE WIDTH HEIGHT MIN | same FILE "
                   "REFERENCE]...\n");
      return 2;
    }
  }
  return candela::problems == 0 ? 0 : 1;
} catch (const std::exception& e) {  // e.g. a JSON field of the wrong type
  std::fprintf(stderr, "check_outputs: %s\n", e.what());
  return 1;
}
