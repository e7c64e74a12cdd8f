#pragma once
// Procedural scenes selectable as builtin:NAME: `cornell` (the classic box with one area light),
// `manylights` (a closed room with a ceiling grid of N coloured emissive quads of widely varying power and
// occluders), `city` (a night city block: emissive windows, street lamps and moving cars with headlights).
#include <string>
#include <vector>

#include "engine/scene.h"

namespace candela {

struct BuiltinOptions {
  int light_count = 1024;  // manylights: number of ceiling quads
  uint64_t seed = 7;       // colours and powers of procedural lights
};

Scene make_cornell_scene();
Scene make_manylights_scene(int light_count, uint64_t seed);
Scene make_city_scene(uint64_t seed);
// A closed sphere (inward-facing, emitting radiance `emission`, diffuse albedo `albedo`): the furnace test,
// where every point sees radiance emission / (1 - albedo).
Scene make_furnace_scene(float albedo, float emission);

// "builtin:NAME" -> scene; throws InputError listing the names for an unknown one.
Scene make_builtin_scene(const std::string& name, const BuiltinOptions& options = {});
std::vector<std::string> builtin_scene_names();

}  // namespace candela
