// Tests of the glTF loader: the shared real scenes load with the expected content, and hand-made broken
// files (tests/data/broken/) either fail with an InputError naming the file or load with a warning.
#include "engine/gltf_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "engine/check.h"
#include "tests/test_util.h"

#ifndef CANDELA_SOURCE_DIR
#error "CANDELA_SOURCE_DIR must be defined as the repository root (tests/CMakeLists.txt does this)"
#endif

namespace candela {
namespace {

std::string broken_file(const std::string& name) {
  return std::string(CANDELA_SOURCE_DIR) + "/tests/data/broken/" + name;
}

// Triangles over unique meshes (the README of the shared scenes counts these, before instancing).
size_t unique_triangles(const Scene& scene) {
  size_t n = 0;
  for (const Mesh& m : scene.meshes) n += m.triangles.size();
  return n;
}

size_t count_lights(const Scene& scene, PunctualType type) {
  return size_t(std::count_if(scene.punctual_lights.begin(), scene.punctual_lights.end(),
                              [&](const PunctualLight& l) { return l.type == type; }));
}

std::vector<const TextureRef*> texture_refs(const Material& m) {
  return {&m.base_color_tex, &m.metallic_roughness_tex, &m.normal_tex,
          &m.emissive_tex,   &m.specular_tex,           &m.specular_color_tex};
}

bool has_warning_containing(const LoadReport& report, const std::string& text) {
  return std::any_of(report.warnings.begin(), report.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

// Invariants every loaded scene must satisfy, whatever the file.
void expect_consistent(const Scene& scene) {
  for (const Mesh& mesh : scene.meshes) {
    SCOPED_TRACE(mesh.name);
    const size_t n = mesh.positions.size();
    EXPECT_FALSE(mesh.triangles.empty());
    for (size_t size : {mesh.normals.size(), mesh.tangents.size(), mesh.uv0.size(), mesh.uv1.size()})
      EXPECT_TRUE(size == 0 || size == n);
    for (const uvec3& t : mesh.triangles) ASSERT_TRUE(t.x < n && t.y < n && t.z < n);
    EXPECT_GE(mesh.material, 0);
    EXPECT_LT(size_t(mesh.material), scene.materials.size());
  }
  for (const Instance& inst : scene.instances) {
    ASSERT_GE(inst.mesh, 0);
    ASSERT_LT(size_t(inst.mesh), scene.meshes.size());
    EXPECT_EQ(inst.transform, inst.prev_transform);
    EXPECT_FALSE(inst.animated);
  }
  for (const Material& m : scene.materials)
    for (const TextureRef* ref : texture_refs(m)) {
      if (!ref->valid()) continue;
      ASSERT_LT(size_t(ref->texture), scene.textures.size());
      const Texture& tex = scene.textures[size_t(ref->texture)];
      EXPECT_EQ(tex.rgba.size(), size_t(tex.width) * size_t(tex.height) * 4);
      EXPECT_TRUE(ref->texcoord == 0 || ref->texcoord == 1);
    }
  for (const PunctualLight& l : scene.punctual_lights) {
    EXPECT_TRUE(is_finite(l.position));
    EXPECT_NEAR(glm::length(l.direction), 1.0f, 1e-4f);
    EXPECT_EQ(l.instance, -1);
  }
}

// ---------------------------------------------------------------------------------------------------
// The shared scenes.

struct SharedScene {
  const char* test_name;
  const char* file;            // relative to the shared scenes directory
  size_t readme_triangles;     // README/gltf_stats "unique" count = loaded unique triangles + skipped
  size_t instanced_triangles;  // Scene::triangle_count() after degenerate triangles are dropped
  size_t point_lights, directional_lights;
};

// nv_cornellbox: its two spheres hold 190 zero-area triangles each (380 skipped); its README count
// (16,720) is over unique meshes while one cube mesh is instanced twice, so the scene holds
// 16,732 - 380 = 16,352 triangles.
const SharedScene kSharedScenes[] = {
    {"CornellBox", "nv_cornellbox/cornellBox.gltf", 16720, 16352, 0, 0},
    {"EmissiveStrengthTest", "EmissiveStrengthTest/glTF/EmissiveStrengthTest.gltf", 90, 90, 0, 0},
    {"LightsPunctualLamp", "LightsPunctualLamp/glTF/LightsPunctualLamp.gltf", 6000, 6000, 5, 0},
    {"StainedGlassLamp", "StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf", 35132, 35132, 0, 0},
    {"DamagedHelmet", "DamagedHelmet/glTF/DamagedHelmet.gltf", 15452, 15452, 0, 0},
    {"GlamVelvetSofa", "GlamVelvetSofa/glTF/GlamVelvetSofa.gltf", 4196, 4196, 0, 1},
};

// Loads a shared scene into `scene`; false (the caller skips) when the shared scenes are not installed.
// When they are, a missing file has already failed the test (testing::shared_scene_file).
bool load_shared(const std::string& relative, Scene& scene, LoadReport& report) {
  const std::string path = testing::shared_scene_file(relative);
  if (path.empty()) return false;
  scene = load_gltf(path, &report);
  return true;
}

class SharedSceneTest : public ::testing::TestWithParam<SharedScene> {};

TEST_P(SharedSceneTest, LoadsWithExpectedCounts) {
  const SharedScene& c = GetParam();
  Scene scene;
  LoadReport report;
  if (!load_shared(c.file, scene, report)) GTEST_SKIP() << testing::shared_scenes_skip_reason();
  EXPECT_EQ(unique_triangles(scene) + report.degenerate_triangles_skipped, c.readme_triangles);
  EXPECT_EQ(scene.triangle_count(), c.instanced_triangles);
  EXPECT_EQ(count_lights(scene, PunctualType::Point), c.point_lights);
  EXPECT_EQ(count_lights(scene, PunctualType::Directional), c.directional_lights);
  EXPECT_EQ(scene.name, std::filesystem::path(c.file).stem().string());
  EXPECT_FALSE(scene.bounds().empty());
  EXPECT_EQ(scene.environment, vec3(0.0f));
  expect_consistent(scene);
}

INSTANTIATE_TEST_SUITE_P(GltfLoader, SharedSceneTest, ::testing::ValuesIn(kSharedScenes),
                         [](const auto& info) { return std::string(info.param.test_name); });

TEST(GltfLoader, CornellBoxInstancesCameraAndImagelessTexture) {
  Scene scene;
  LoadReport report;
  if (!load_shared("nv_cornellbox/cornellBox.gltf", scene, report))
    GTEST_SKIP() << testing::shared_scenes_skip_reason();
  // One cube mesh is used by two nodes: one Mesh, two Instances.
  EXPECT_EQ(scene.meshes.size(), 9u);
  EXPECT_EQ(scene.instances.size(), 10u);
  EXPECT_EQ(report.degenerate_triangles_skipped, 380u);
  ASSERT_TRUE(scene.camera.has_value());
  EXPECT_NEAR(scene.camera->vfov_degrees, glm::degrees(0.7175414562225342f), 1e-3f);
  EXPECT_NEAR(scene.camera->position.z, 19.99209f, 1e-3f);
  EXPECT_LT(scene.camera->target.z, scene.camera->position.z);  // looks along -Z
  // The texture without an image loads with a warning and no material points at it.
  EXPECT_TRUE(has_warning_containing(report, "texture 0"));
  for (const Material& m : scene.materials)
    for (const TextureRef* ref : texture_refs(m)) EXPECT_FALSE(ref->valid());
  // emissiveFactor 3.0 is kept as is, without a warning.
  float max_emission = 0.0f;
  for (const Material& m : scene.materials) max_emission = std::max(max_emission, max_component(m.emission));
  EXPECT_FLOAT_EQ(max_emission, 3.0f);
  EXPECT_FALSE(has_warning_containing(report, "emissiveFactor"));
}

TEST(GltfLoader, EmissiveStrengthMultipliesEmission) {
  Scene scene;
  LoadReport report;
  if (!load_shared("EmissiveStrengthTest/glTF/EmissiveStrengthTest.gltf", scene, report))
    GTEST_SKIP() << testing::shared_scenes_skip_reason();
  // emissiveFactor (0.1, 0.5, 0.9) with emissiveStrength up to 16.
  float max_emission = 0.0f;
  for (const Material& m : scene.materials) max_emission = std::max(max_emission, max_component(m.emission));
  EXPECT_GE(max_emission, 16.0f * 0.9f * 0.9999f);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
}

TEST(GltfLoader, LampLightsArePlacedThroughNodes) {
  Scene scene;
  LoadReport report;
  if (!load_shared("LightsPunctualLamp/glTF/LightsPunctualLamp.gltf", scene, report))
    GTEST_SKIP() << testing::shared_scenes_skip_reason();
  ASSERT_EQ(scene.punctual_lights.size(), 5u);
  // The bulb light (node "Point_Orientation") sits at its node matrix's translation, inside the lamp.
  const PunctualLight& bulb = scene.punctual_lights[0];
  EXPECT_NEAR(bulb.position.x, 0.04622f, 1e-4f);
  EXPECT_NEAR(bulb.position.y, 0.90780f, 1e-4f);
  EXPECT_NEAR(bulb.position.z, 0.00670f, 1e-4f);
  EXPECT_NEAR(bulb.intensity.x, 15.0f, 1e-4f);  // colour (1, 0.63, 0.24) * intensity 15
  Bounds3 bounds = scene.bounds();
  EXPECT_TRUE(glm::all(glm::greaterThanEqual(bulb.position, bounds.lo)) &&
              glm::all(glm::lessThanEqual(bulb.position, bounds.hi)));
  // The other four are fill lights around the lamp (some outside its mesh bounds, as in the file):
  // all lie inside the bounds grown by one diagonal.
  const vec3 margin(bounds.diagonal());
  for (const PunctualLight& l : scene.punctual_lights) {
    EXPECT_TRUE(glm::all(glm::greaterThanEqual(l.position, bounds.lo - margin)) &&
                glm::all(glm::lessThanEqual(l.position, bounds.hi + margin)));
    EXPECT_NEAR(l.direction.y, -1.0f, 1e-4f);  // node rotation turns -Z into -Y
  }
}

TEST(GltfLoader, SofaTextureTransformAndDirectionalLight) {
  Scene scene;
  LoadReport report;
  if (!load_shared("GlamVelvetSofa/glTF/GlamVelvetSofa.gltf", scene, report))
    GTEST_SKIP() << testing::shared_scenes_skip_reason();
  bool transformed = false;
  for (const Material& m : scene.materials)
    for (const TextureRef* ref : texture_refs(m))
      transformed |= ref->valid() && (ref->scale != vec2(1.0f) || ref->offset != vec2(0.0f) || ref->rotation != 0.0f);
  EXPECT_TRUE(transformed);
  // The fabric materials use normalTexture with scale (5, 5) and rotation 0.36.
  bool found = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
    return m.normal_tex.valid() && m.normal_tex.scale == vec2(5.0f) && std::abs(m.normal_tex.rotation - 0.36f) < 1e-6f;
  });
  EXPECT_TRUE(found);
  ASSERT_EQ(scene.punctual_lights.size(), 1u);
  EXPECT_LT(scene.punctual_lights[0].direction.z, 0.5f);  // rotated away from the default -Z
  EXPECT_GT(scene.punctual_lights[0].direction.x, 0.5f);
}

// ---------------------------------------------------------------------------------------------------
// Broken files that must be refused.

struct BrokenFile {
  const char* test_name;
  const char* file;      // in tests/data/broken/ (some deliberately do not exist)
  const char* fragment;  // expected in the message besides the file name
};

const BrokenFile kBrokenFiles[] = {
    {"MissingBufferFile", "missing_buffer.gltf", "missing_buffer_data.bin"},
    {"IndexOutOfRange", "index_out_of_range.gltf", "index 5"},
    {"AccessorPastEndOfBufferView", "accessor_past_end.gltf", "past the end of bufferView"},
    {"BufferViewPastEndOfBuffer", "bufferview_past_buffer.gltf", "past the end of buffer"},
    {"NanPosition", "nan_position.gltf", "POSITION accessor 0"},
    {"BufferViewIndexOutOfRange", "bufferview_out_of_range.gltf", "bufferView 7 does not exist"},
    {"InvalidJson", "invalid_json.gltf", ""},
    {"TruncatedGlb", "truncated.glb", ""},
    {"FileDoesNotExist", "does_not_exist.gltf", "does not exist"},
    {"WrongExtension", "scene.obj", ".gltf or .glb"},
    {"NodeCycle", "node_cycle.gltf", "reached twice"},
    {"InvalidComponentType", "bad_component_type.gltf", "componentType 5124"},
    {"MaterialOutOfRange", "material_out_of_range.gltf", "material 3 does not exist"},
    {"AttributeCountMismatch", "count_mismatch.gltf", "NORMAL"},
    // Hostile input (engine/input_limits.h): too deep to parse, or not representable in float ray arithmetic.
    {"DeepNestingGltf", "deep_nesting.gltf", "JSON nested deeper than 512 levels"},
    {"DeepNestingGlb", "deep_nesting.glb", "JSON nested deeper than 512 levels"},
    {"HugePosition", "huge_position.gltf", "POSITION accessor 0: coordinate 1e+38 is beyond the limit of 1e+08"},
    {"HugeNodeScale", "huge_node_scale.gltf", "node 0 'giant': world-space coordinate 1e+25 is beyond the limit"},
    {"FarCamera", "far_camera.gltf", "node 1 'far_eye': camera position 1e+30 is beyond the limit"},
    {"HugeEmission", "huge_emission.gltf", "material 0 'hot': emission"},
};

class BrokenFileTest : public ::testing::TestWithParam<BrokenFile> {};

TEST_P(BrokenFileTest, ThrowsInputErrorNamingTheFile) {
  const BrokenFile& c = GetParam();
  const std::string path = broken_file(c.file);
  EXPECT_THROW(load_gltf(path), InputError);
  try {
    LoadReport report;
    load_gltf(path, &report);
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(c.file), std::string::npos) << message;
    EXPECT_NE(message.find(c.fragment), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(GltfLoader, BrokenFileTest, ::testing::ValuesIn(kBrokenFiles),
                         [](const auto& info) { return std::string(info.param.test_name); });

// ---------------------------------------------------------------------------------------------------
// Broken files that still load, with warnings.

TEST(GltfLoader, OutOfRangeFactorsAreClampedWithWarning) {
  LoadReport report;
  Scene scene = load_gltf(broken_file("bad_roughness.gltf"), &report);
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].roughness, 1.0f);
  EXPECT_EQ(scene.materials[0].metallic, 0.0f);
  EXPECT_TRUE(has_warning_containing(report, "roughnessFactor"));
  EXPECT_TRUE(has_warning_containing(report, "metallicFactor"));
  EXPECT_TRUE(has_warning_containing(report, "bad_roughness.gltf"));
}

TEST(GltfLoader, DegenerateTriangleIsSkippedAndCounted) {
  LoadReport report;
  Scene scene = load_gltf(broken_file("degenerate_triangle.gltf"), &report);
  EXPECT_EQ(scene.triangle_count(), 1u);
  EXPECT_EQ(report.degenerate_triangles_skipped, 1u);
  // No material in the file: the default one is appended.
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.meshes[0].material, 0);
  EXPECT_TRUE(scene.meshes[0].normals.empty());  // no NORMAL: left to geometric normals
  expect_consistent(scene);
}

TEST(GltfLoader, UnusableImagesLeaveMaterialSlotsEmpty) {
  LoadReport report;
  Scene scene = load_gltf(broken_file("bad_images.gltf"), &report);
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_FALSE(scene.materials[0].base_color_tex.valid());  // bufferView bytes that are not a PNG
  EXPECT_FALSE(scene.materials[0].emissive_tex.valid());    // image file missing
  EXPECT_EQ(scene.textures.size(), 2u);                     // placeholders keep glTF indices
  EXPECT_TRUE(has_warning_containing(report, "texture 0"));
  EXPECT_TRUE(has_warning_containing(report, "texture 1"));
  expect_consistent(scene);
}

TEST(GltfLoader, ReportIsOptional) {
  Scene scene = load_gltf(broken_file("degenerate_triangle.gltf"));
  EXPECT_EQ(scene.name, "degenerate_triangle");
  EXPECT_EQ(scene.instances.size(), 1u);
}

}  // namespace
}  // namespace candela
