#include "engine/builtin_scenes.h"

#include <glm/gtc/matrix_transform.hpp>
#include <map>

#include "engine/check.h"
#include "engine/rng.h"

namespace candela {

namespace {

// Collects procedural geometry into one mesh per material, each placed by one identity instance.
class SceneBuilder {
 public:
  int material(const vec3& base, float roughness = 0.8f, const vec3& emission = vec3(0.0f), float metallic = 0.0f) {
    Material m;
    m.base_color = vec4(base, 1.0f);
    m.roughness = roughness;
    m.metallic = metallic;
    m.emission = emission;
    scene_.materials.push_back(m);
    return int(scene_.materials.size() - 1);
  }
  // Quad centred at c spanned by half-edges u and v, wound so that it faces `facing`.
  void quad(int mat, const vec3& c, vec3 u, const vec3& v, const vec3& facing) {
    if (glm::dot(glm::cross(u, v), facing) < 0.0f) u = -u;
    Mesh& m = mesh(mat);
    uint32_t b = uint32_t(m.positions.size());
    vec3 n = glm::normalize(glm::cross(u, v));
    for (vec3 p : {c - u - v, c + u - v, c + u + v, c - u + v}) {
      m.positions.push_back(p);
      m.normals.push_back(n);
    }
    m.triangles.push_back(uvec3(b, b + 1, b + 2));
    m.triangles.push_back(uvec3(b, b + 2, b + 3));
  }
  // Box with outward faces, half extents h, turned by `yaw` radians about +y; `skip_bottom` omits the floor face.
  void box(int mat, const vec3& c, const vec3& h, float yaw = 0.0f, bool skip_bottom = false) {
    vec3 x(std::cos(yaw), 0.0f, -std::sin(yaw)), y(0.0f, 1.0f, 0.0f), z(std::sin(yaw), 0.0f, std::cos(yaw));
    quad(mat, c + x * h.x, z * h.z, y * h.y, x);
    quad(mat, c - x * h.x, z * h.z, y * h.y, -x);
    quad(mat, c + y * h.y, x * h.x, z * h.z, y);
    if (!skip_bottom) quad(mat, c - y * h.y, x * h.x, z * h.z, -y);
    quad(mat, c + z * h.z, x * h.x, y * h.y, z);
    quad(mat, c - z * h.z, x * h.x, y * h.y, -z);
  }
  // Moves the geometry gathered so far into meshes with identity instances and returns the scene.
  Scene finish() {
    for (auto& [mat, mesh] : meshes_) {
      if (mesh.triangles.empty()) continue;
      mesh.material = mat;
      scene_.meshes.push_back(std::move(mesh));
      scene_.instances.push_back(Instance{int(scene_.meshes.size() - 1)});
    }
    meshes_.clear();
    return std::move(scene_);
  }
  Scene& scene() { return scene_; }

 private:
  Mesh& mesh(int mat) { return meshes_[mat]; }
  Scene scene_;
  std::map<int, Mesh> meshes_;
};

vec3 hue_color(float h) {
  vec3 c = glm::clamp(glm::abs(glm::mod(h * 6.0f + vec3(0.0f, 4.0f, 2.0f), 6.0f) - 3.0f) - 1.0f, 0.0f, 1.0f);
  return glm::mix(vec3(1.0f), c, 0.7f);
}

}  // namespace

Scene make_cornell_scene() {
  SceneBuilder b;
  int white = b.material(vec3(0.73f)), red = b.material(vec3(0.65f, 0.05f, 0.05f)),
      green = b.material(vec3(0.12f, 0.45f, 0.15f)), light = b.material(vec3(0.78f), 0.8f, vec3(17.0f, 12.0f, 4.0f));
  b.quad(white, vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 0, 1), vec3(0, 1, 0));   // floor
  b.quad(white, vec3(0, 2, 0), vec3(1, 0, 0), vec3(0, 0, 1), vec3(0, -1, 0));  // ceiling
  b.quad(white, vec3(0, 1, -1), vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1));  // back wall
  b.quad(red, vec3(-1, 1, 0), vec3(0, 0, 1), vec3(0, 1, 0), vec3(1, 0, 0));    // left wall
  b.quad(green, vec3(1, 1, 0), vec3(0, 0, 1), vec3(0, 1, 0), vec3(-1, 0, 0));  // right wall
  b.quad(light, vec3(0, 1.995f, 0), vec3(0.25f, 0, 0), vec3(0, 0, 0.2f), vec3(0, -1, 0));
  b.box(white, vec3(0.33f, 0.3f, 0.3f), vec3(0.3f, 0.3f, 0.3f), -0.3f, true);
  b.box(white, vec3(-0.33f, 0.6f, -0.3f), vec3(0.3f, 0.6f, 0.3f), 0.3f, true);
  Scene s = b.finish();
  s.name = "cornell";
  s.camera = CameraDesc{vec3(0, 1, 3.9f), vec3(0, 1, 0), vec3(0, 1, 0), 38.0f};
  return s;
}

Scene make_manylights_scene(int light_count, uint64_t seed) {
  if (light_count < 1 || light_count > 4'000'000)
    throw InputError("builtin:manylights: light count must be in [1, 4000000], got " + std::to_string(light_count));
  SceneBuilder b;
  const float half = 10.0f, height = 5.0f;
  int wall = b.material(vec3(0.7f)), floor = b.material(vec3(0.5f, 0.45f, 0.4f), 0.5f),
      block = b.material(vec3(0.6f, 0.62f, 0.7f), 0.6f),
      metal = b.material(vec3(0.9f, 0.8f, 0.6f), 0.3f, vec3(0.0f), 1.0f);
  b.quad(floor, vec3(0, 0, 0), vec3(half, 0, 0), vec3(0, 0, half), vec3(0, 1, 0));
  b.quad(wall, vec3(0, height, 0), vec3(half, 0, 0), vec3(0, 0, half), vec3(0, -1, 0));
  b.quad(wall, vec3(0, height / 2, -half), vec3(half, 0, 0), vec3(0, height / 2, 0), vec3(0, 0, 1));
  b.quad(wall, vec3(0, height / 2, half), vec3(half, 0, 0), vec3(0, height / 2, 0), vec3(0, 0, -1));
  b.quad(wall, vec3(-half, height / 2, 0), vec3(0, 0, half), vec3(0, height / 2, 0), vec3(1, 0, 0));
  b.quad(wall, vec3(half, height / 2, 0), vec3(0, 0, half), vec3(0, height / 2, 0), vec3(-1, 0, 0));
  // Occluders: pillars, a partition wall and low blocks, so that most lights are hidden from most points.
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      if (i != 0 || j != 0) b.box(block, vec3(i * 5.0f, 2.0f, j * 5.0f), vec3(0.4f, 2.0f, 0.4f), 0.0f, true);
  b.box(block, vec3(-3.0f, 1.5f, 1.0f), vec3(3.0f, 1.5f, 0.15f), 0.0f, true);
  b.box(metal, vec3(3.0f, 0.5f, -2.0f), vec3(1.0f, 0.5f, 0.7f), 0.5f, true);
  b.box(block, vec3(-5.5f, 0.6f, -6.0f), vec3(1.2f, 0.6f, 1.2f), 0.9f, true);

  // Ceiling grid: N quads, each with one of 64 palette materials (random hue, power log-uniform over 4 decades).
  Rng rng(seed, 0x11);
  std::vector<int> palette;
  for (int k = 0; k < 64; ++k) {
    float power = std::pow(10.0f, rng.next_float() * 4.0f - 2.5f);
    palette.push_back(b.material(vec3(0.8f), 0.8f, hue_color(rng.next_float()) * power));
  }
  int grid = int(std::ceil(std::sqrt(float(light_count))));
  float cell = 2.0f * half / float(grid);
  float size = std::min(0.3f * cell, 0.25f);
  for (int k = 0; k < light_count; ++k) {
    int gx = k % grid, gz = k / grid;
    vec3 c(-half + (gx + 0.5f) * cell, height - 0.01f, -half + (gz + 0.5f) * cell);
    int mat = palette[rng.next_u32() % palette.size()];
    b.quad(mat, c, vec3(size, 0, 0), vec3(0, 0, size), vec3(0, -1, 0));
  }
  Scene s = b.finish();
  s.name = "manylights";
  s.camera = CameraDesc{vec3(8.5f, 2.2f, 8.5f), vec3(-2.0f, 1.2f, -2.0f), vec3(0, 1, 0), 60.0f};
  return s;
}

// A night city block: a grid of towers whose facades carry lit and dark windows, street lamps along the
// streets, and cars (body, headlights, tail lights, two spot lights each) driving along the streets.
Scene make_city_scene(uint64_t seed) {
  SceneBuilder b;
  Rng rng(seed, 0x22);
  const int blocks = 16;
  const float spacing = 14.0f, street = 5.0f, extent = blocks * spacing * 0.5f;
  int asphalt = b.material(vec3(0.08f), 0.7f), sidewalk = b.material(vec3(0.25f), 0.8f),
      facade = b.material(vec3(0.35f, 0.33f, 0.3f), 0.7f), dark_window = b.material(vec3(0.05f, 0.06f, 0.08f), 0.1f),
      pole = b.material(vec3(0.2f), 0.4f, vec3(0.0f), 1.0f);
  std::vector<int> window_lights;
  for (vec3 c : {vec3(1.0f, 0.75f, 0.45f), vec3(1.0f, 0.9f, 0.7f), vec3(0.7f, 0.8f, 1.0f), vec3(1.0f, 0.6f, 0.3f)})
    for (float power : {0.5f, 1.5f, 4.0f}) window_lights.push_back(b.material(vec3(0.8f), 0.2f, c * power));
  int lamp = b.material(vec3(0.9f), 0.5f, vec3(40.0f, 30.0f, 18.0f));
  b.quad(asphalt, vec3(0), vec3(extent + 40.0f, 0, 0), vec3(0, 0, extent + 40.0f), vec3(0, 1, 0));

  for (int i = 0; i < blocks; ++i) {
    for (int j = 0; j < blocks; ++j) {
      vec3 c(-extent + (i + 0.5f) * spacing, 0.0f, -extent + (j + 0.5f) * spacing);
      float w = 0.5f * (spacing - street);
      b.box(sidewalk, c + vec3(0, 0.075f, 0), vec3(w, 0.075f, w), 0.0f, true);
      float bw = w - 0.8f, bh = 12.0f + rng.next_float() * 40.0f;
      b.box(facade, c + vec3(0, bh * 0.5f + 0.15f, 0), vec3(bw, bh * 0.5f, bw), 0.0f, true);
      // Windows on the four facades: 3 m floors, 1 m columns, 70% lit.
      int floors = int(bh / 3.0f), cols = int(2.0f * bw);
      for (int side = 0; side < 4; ++side) {
        vec3 n = side == 0 ? vec3(1, 0, 0) : side == 1 ? vec3(-1, 0, 0) : side == 2 ? vec3(0, 0, 1) : vec3(0, 0, -1);
        vec3 along = vec3(n.z, 0, -n.x);
        for (int f = 0; f < floors; ++f) {
          for (int k = 0; k < cols; ++k) {
            vec3 wc = c + n * (bw + 0.02f) + along * (-bw + (k + 0.5f) * (2.0f * bw / cols)) +
                      vec3(0, 0.15f + 1.6f + f * 3.0f, 0);
            bool lit = rng.next_float() < 0.7f;
            int mat = lit ? window_lights[rng.next_u32() % window_lights.size()] : dark_window;
            b.quad(mat, wc, along * 0.3f, vec3(0, 0.8f, 0), n);
          }
        }
      }
      // A street lamp at the block's corner: a pole and a glowing head facing down.
      vec3 lp = c + vec3(w - 0.3f, 0.0f, w - 0.3f);
      b.box(pole, lp + vec3(0, 3.0f, 0), vec3(0.08f, 3.0f, 0.08f), 0.0f, true);
      b.box(lamp, lp + vec3(0, 6.1f, 0), vec3(0.3f, 0.08f, 0.3f));
    }
  }
  Scene s = b.finish();

  // Cars: three meshes in car space (+z forward), instanced per car and moved along the streets.
  SceneBuilder car;
  int body = car.material(vec3(0.6f, 0.1f, 0.1f), 0.3f, vec3(0.0f), 0.6f);
  int head = car.material(vec3(1.0f), 0.5f, vec3(60.0f, 55.0f, 45.0f));
  int tail = car.material(vec3(1.0f), 0.5f, vec3(30.0f, 1.0f, 1.0f));
  car.box(body, vec3(0, 0.55f, 0), vec3(0.9f, 0.35f, 2.1f), 0.0f, true);
  car.box(body, vec3(0, 1.1f, -0.2f), vec3(0.8f, 0.25f, 1.1f), 0.0f, true);
  for (float x : {-0.6f, 0.6f}) {
    car.quad(head, vec3(x, 0.6f, 2.11f), vec3(0.18f, 0, 0), vec3(0, 0.09f, 0), vec3(0, 0, 1));
    car.quad(tail, vec3(x, 0.65f, -2.11f), vec3(0.18f, 0, 0), vec3(0, 0.07f, 0), vec3(0, 0, -1));
  }
  Scene car_scene = car.finish();
  int material_base = int(s.materials.size()), mesh_base = int(s.meshes.size());
  for (Material& m : car_scene.materials) s.materials.push_back(m);
  for (Mesh& m : car_scene.meshes) {
    m.material += material_base;
    s.meshes.push_back(std::move(m));
  }
  const int cars = 48;
  for (int k = 0; k < cars; ++k) {
    // Streets run between blocks along x or z; cars drive in the right-hand lane of a random street.
    bool along_x = k % 2 == 0;
    int lane_street = int(rng.next_u32() % (blocks + 1));
    float dir = rng.next_float() < 0.5f ? 1.0f : -1.0f;
    float offset = -extent + lane_street * spacing + dir * 1.2f;
    float yaw = along_x ? (dir > 0 ? kPi / 2 : -kPi / 2) : (dir > 0 ? 0.0f : kPi);
    vec3 heading = along_x ? vec3(dir, 0, 0) : vec3(0, 0, dir);
    // The street's start (the car wraps back to it after 2 * extent), and where along it the car is at t = 0.
    vec3 origin = (along_x ? vec3(0.0f, 0.0f, offset) : vec3(offset, 0.0f, 0.0f)) - heading * extent;
    float phase = rng.next_float() * 2.0f * extent;
    mat4 start_transform = glm::rotate(glm::translate(mat4(1.0f), origin), yaw, vec3(0, 1, 0));
    float speed = 8.0f + rng.next_float() * 6.0f;
    for (int m = 0; m < int(car_scene.meshes.size()); ++m) {
      s.instances.push_back(Instance{mesh_base + m, start_transform, start_transform, true});
      s.motions.push_back(
          InstanceMotion{int(s.instances.size() - 1), start_transform, heading * speed, 2.0f * extent, phase});
    }
    // Two headlight spots attached to the car body's instance.
    int body_instance = int(s.instances.size() - car_scene.meshes.size());
    for (float x : {-0.6f, 0.6f}) {
      PunctualLight spot;
      spot.type = PunctualType::Spot;
      spot.position = vec3(x, 0.6f, 2.2f);
      spot.direction = glm::normalize(vec3(0.0f, -0.15f, 1.0f));
      spot.intensity = vec3(400.0f, 380.0f, 330.0f);
      spot.inner_cone = 0.25f;
      spot.outer_cone = 0.5f;
      spot.instance = body_instance;
      s.punctual_lights.push_back(spot);
    }
  }
  s.set_time(0.0f);
  s.set_time(0.0f);  // twice, so that prev_transform also holds the t = 0 placement
  s.name = "city";
  s.environment = vec3(0.004f, 0.006f, 0.012f);
  // Looking down the central street (x = 0) from above its end.
  s.camera = CameraDesc{vec3(2.0f, 30.0f, extent + 25.0f), vec3(0.0f, 2.0f, extent * 0.2f), vec3(0, 1, 0), 50.0f};
  return s;
}

// An icosphere subdivided 4 times (5120 triangles), inward-facing, closed.
Scene make_furnace_scene(float albedo, float emission) {
  std::vector<vec3> v;
  std::vector<uvec3> f;
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  for (vec3 p : {vec3(-1, t, 0), vec3(1, t, 0), vec3(-1, -t, 0), vec3(1, -t, 0), vec3(0, -1, t), vec3(0, 1, t),
                 vec3(0, -1, -t), vec3(0, 1, -t), vec3(t, 0, -1), vec3(t, 0, 1), vec3(-t, 0, -1), vec3(-t, 0, 1)})
    v.push_back(glm::normalize(p));
  f = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
       {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < 4; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t c) {
      auto key = std::minmax(a, c);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[c]));
      return midpoint[key] = uint32_t(v.size() - 1);
    };
    std::vector<uvec3> next;
    for (const uvec3& tri : f) {
      uint32_t a = mid(tri.x, tri.y), bb = mid(tri.y, tri.z), c = mid(tri.z, tri.x);
      next.insert(next.end(), {uvec3(tri.x, a, c), uvec3(tri.y, bb, a), uvec3(tri.z, c, bb), uvec3(a, bb, c)});
    }
    f = std::move(next);
  }
  Scene s;
  s.name = "furnace";
  Mesh mesh;
  mesh.positions = v;
  for (const uvec3& tri : f) mesh.triangles.push_back(uvec3(tri.x, tri.z, tri.y));  // wind inward
  Material m;
  m.base_color = vec4(vec3(albedo), 1.0f);
  m.emission = vec3(emission);
  m.roughness = 1.0f;
  m.specular = 0.0f;  // a pure Lambert reflector, so that the albedo is exactly `albedo`
  s.materials.push_back(m);
  s.meshes.push_back(std::move(mesh));
  s.instances.push_back(Instance{0});
  s.camera = CameraDesc{vec3(0.0f), vec3(0.0f, 0.0f, -1.0f), vec3(0, 1, 0), 60.0f};
  return s;
}

std::vector<std::string> builtin_scene_names() { return {"cornell", "manylights", "city"}; }

Scene make_builtin_scene(const std::string& name, const BuiltinOptions& options) {
  if (name == "cornell") return make_cornell_scene();
  if (name == "manylights") return make_manylights_scene(options.light_count, options.seed);
  if (name == "city") return make_city_scene(options.seed);
  throw InputError("unknown built-in scene 'builtin:" + name +
                   "' (known: builtin:cornell, builtin:manylights, builtin:city)");
}

}  // namespace candela
