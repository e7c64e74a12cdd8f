#include "engine/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <sstream>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/check.h"
#include "engine/input_limits.h"

namespace candela {
namespace {

using tinygltf::Value;

// Larger accessors are refused before anything is allocated for them.
constexpr size_t kMaxAccessorElements = size_t(1) << 28;

// ---------------------------------------------------------------------------------------------------
// Context: the file being converted, its parsed model and where findings go.

struct Context {
  std::string file;  // the path as given; prefixes every message
  const tinygltf::Model& model;
  LoadReport& report;

  [[noreturn]] void fail(const std::string& what) const { throw InputError(file + ": " + what); }
  void warn(const std::string& what) const { report.warnings.push_back(file + ": " + what); }
};

std::string quoted_name(const std::string& name) { return name.empty() ? "" : " '" + name + "'"; }

std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

// Throws unless 0 <= index < size; `what` names the kind of object referenced ("accessor", ...).
void check_index(const Context& ctx, int index, size_t size, const std::string& what, const std::string& where) {
  if (index < 0 || size_t(index) >= size)
    ctx.fail(where + ": " + what + " " + std::to_string(index) + " does not exist (the file has " +
             std::to_string(size) + ")");
}

// ---------------------------------------------------------------------------------------------------
// Representable values (limits and reasons in engine/input_limits.h): world-space coordinates and
// emission that the tracer's float arithmetic can take without overflowing to inf or NaN.

// Throws unless `value` is finite and at most `limit` in magnitude; `what` names the value and its place.
void check_magnitude(const Context& ctx, double value, float limit, const std::string& what) {
  if (!(std::abs(value) <= double(limit)))
    ctx.fail(what + " " + format_number(value) + " is beyond the limit of " + format_number(limit) +
             " (see engine/input_limits.h)");
}

// The component of `p` largest in magnitude (NaN if any is NaN), to check a point with one message.
float largest_component(const vec3& p) {
  if (!is_finite(p)) return std::numeric_limits<float>::quiet_NaN();
  const vec3 a = glm::abs(p);
  return a.x >= a.y && a.x >= a.z ? p.x : a.y >= a.z ? p.y : p.z;
}

void check_point(const Context& ctx, const vec3& p, const std::string& what) {
  check_magnitude(ctx, largest_component(p), kMaxCoordinate, what);
}

// Throws unless the 8 corners of `object` (a mesh's bounds) placed by `transform` lie within the limit.
void check_placed_bounds(const Context& ctx, const Bounds3& object, const mat4& transform, const std::string& where) {
  for (int corner = 0; corner < 8; ++corner) {
    vec3 p((corner & 1) ? object.hi.x : object.lo.x, (corner & 2) ? object.hi.y : object.lo.y,
           (corner & 4) ? object.hi.z : object.lo.z);
    check_point(ctx, transform_point(transform, p), where + ": world-space coordinate");
  }
}

// ---------------------------------------------------------------------------------------------------
// JSON values of extensions (tinygltf::Value asserts on wrong types, so every access is checked here).

const Value* member(const Value& object, const char* key) {
  if (!object.IsObject() || !object.Has(key)) return nullptr;
  return &object.Get(key);
}

const Value* extension(const tinygltf::ExtensionMap& extensions, const char* name) {
  auto it = extensions.find(name);
  return it != extensions.end() && it->second.IsObject() ? &it->second : nullptr;
}

std::optional<double> number(const Value* v) {
  if (v == nullptr || !v->IsNumber()) return std::nullopt;
  return v->GetNumberAsDouble();
}

// A JSON array of exactly n finite numbers.
std::optional<std::vector<double>> numbers(const Value* v, size_t n) {
  if (v == nullptr || !v->IsArray() || v->ArrayLen() != n) return std::nullopt;
  std::vector<double> out;
  for (size_t i = 0; i < n; ++i) {
    const Value& e = v->Get(int(i));
    if (!e.IsNumber() || !std::isfinite(e.GetNumberAsDouble())) return std::nullopt;
    out.push_back(e.GetNumberAsDouble());
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Reading the file: tinygltf parses JSON/GLB, loads buffers and decodes images referenced by URI.

// A tinygltf message (often several lines, with a trailing newline) as one line.
std::string one_line(const std::string& text) {
  std::string out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (line.empty()) continue;
    if (!out.empty()) out += "; ";
    out += line;
  }
  return out;
}

// Image callback for tinygltf: decodes URI images but never fails the load (an undecodable image is a
// warning and stays empty); images stored in bufferViews are left for decode_embedded_images, which
// checks their byte range first.
bool decode_image_leniently(tinygltf::Image* image, const int index, std::string* /*err*/, std::string* warn,
                            int req_width, int req_height, const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  std::string decode_error;
  if (!tinygltf::LoadImageData(image, index, &decode_error, warn, req_width, req_height, bytes, size, nullptr)) {
    image->image.clear();
    if (warn) *warn += "image " + std::to_string(index) + " could not be decoded: " + one_line(decode_error) + "\n";
  }
  return true;
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// Adds each line of a tinygltf message to the report's warnings.
void add_warning_lines(const Context& ctx, const std::string& text) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    line = one_line(line);
    if (!line.empty()) ctx.warn(line);
  }
}

// The whole file as bytes; tinygltf takes at most 4 GiB (an unsigned int size).
std::string read_file_bytes(const Context& ctx) {
  std::ifstream in(ctx.file, std::ios::binary);
  if (!in) ctx.fail("cannot open the file");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) ctx.fail("read failed");
  std::string data = std::move(bytes).str();
  if (data.empty()) ctx.fail("the file is empty");
  if (data.size() > std::numeric_limits<unsigned int>::max()) ctx.fail("larger than 4 GiB");
  return data;
}

// The JSON text of a .gltf file, or of a .glb file's first chunk (bytes 20.. after the 12-byte header and
// the chunk's length and type), clipped to the file; a GLB too short for that has none to scan.
std::string_view json_text(const std::string& data, bool binary) {
  if (!binary) return data;
  if (data.size() < 20) return {};
  uint32_t chunk_length = 0;
  std::memcpy(&chunk_length, data.data() + 12, 4);
  return std::string_view(data).substr(20, chunk_length);
}

// Reads `path` (.gltf or .glb) into a tinygltf model, after bounding its JSON nesting (the parser
// recurses per level); tinygltf's errors become an InputError, its warnings go to the report.
tinygltf::Model read_model(const Context& ctx) {
  std::string ext = lower_extension(ctx.file);
  if (ext != ".gltf" && ext != ".glb") ctx.fail("not a glTF file (expected the extension .gltf or .glb)");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(ctx.file, ec)) ctx.fail("file does not exist or is not a regular file");
  const std::string data = read_file_bytes(ctx);
  check_json_nesting(json_text(data, ext == ".glb"), ctx.file);

  tinygltf::TinyGLTF parser;
  parser.SetImageLoader(decode_image_leniently, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  // Relative URIs resolve against the file's directory, as tinygltf's *FromFile functions do.
  const std::string base_dir = std::filesystem::path(ctx.file).parent_path().string();
  const auto size = static_cast<unsigned int>(data.size());
  bool ok = false;
  try {
    ok = ext == ".glb" ? parser.LoadBinaryFromMemory(
                             &model, &err, &warn, reinterpret_cast<const unsigned char*>(data.data()), size, base_dir)
                       : parser.LoadASCIIFromString(&model, &err, &warn, data.data(), size, base_dir);
  } catch (const std::exception& e) {
    ctx.fail(std::string("cannot parse: ") + e.what());
  }
  if (!ok) ctx.fail(err.empty() ? "cannot parse (tinygltf gave no reason)" : one_line(err));
  add_warning_lines(ctx, warn);
  add_warning_lines(ctx, err);
  return model;
}

// Refuses files whose required extensions change how geometry is stored; warns about other unknown ones.
void check_required_extensions(const Context& ctx) {
  static const char* const kSupported[] = {"KHR_texture_transform",  "KHR_materials_emissive_strength",
                                           "KHR_materials_specular", "KHR_materials_ior",
                                           "KHR_lights_punctual",    "KHR_mesh_quantization"};
  static const char* const kGeometry[] = {"KHR_draco_mesh_compression", "EXT_meshopt_compression"};
  for (const std::string& name : ctx.model.extensionsRequired) {
    if (std::find(std::begin(kSupported), std::end(kSupported), name) != std::end(kSupported)) continue;
    if (std::find(std::begin(kGeometry), std::end(kGeometry), name) != std::end(kGeometry))
      ctx.fail("requires extension " + name + ", which this loader cannot decode");
    ctx.warn("requires extension " + name + ", which is ignored");
  }
  if (!ctx.model.skins.empty()) ctx.warn("skins are ignored (meshes are loaded in their bind pose)");
}

// ---------------------------------------------------------------------------------------------------
// Accessors: validated byte windows into buffers, decoded to doubles.

int component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;  // INT, DOUBLE and unknown values are not valid glTF accessor types
  }
}

bool is_unsigned_integer(int component_type) {
  return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    default: return "a matrix type";
  }
}

// One component at p; normalised integers map to [0, 1] (unsigned) or [-1, 1] (signed).
double read_component(const uint8_t* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? v / 255.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// `count` elements of `element_size` bytes; element i starts at data + i * stride.
struct ElementSpan {
  const uint8_t* data = nullptr;
  size_t count = 0, stride = 0;
};

// Checks that `count` elements starting `offset` bytes into bufferView `view_index` lie inside the view
// and the view inside its buffer. `strided` honours the view's byteStride (vertex attributes only).
ElementSpan element_span(const Context& ctx, int view_index, size_t offset, size_t count, size_t element_size,
                         bool strided, const std::string& where) {
  const tinygltf::Model& m = ctx.model;
  check_index(ctx, view_index, m.bufferViews.size(), "bufferView", where);
  const tinygltf::BufferView& view = m.bufferViews[size_t(view_index)];
  std::string view_where = where + " (bufferView " + std::to_string(view_index) + ")";
  check_index(ctx, view.buffer, m.buffers.size(), "buffer", view_where);
  const size_t buffer_size = m.buffers[size_t(view.buffer)].data.size();
  if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset)
    ctx.fail(view_where + ": bytes " + std::to_string(view.byteOffset) + ".." +
             std::to_string(view.byteOffset + view.byteLength) + " lie past the end of buffer " +
             std::to_string(view.buffer) + " (" + std::to_string(buffer_size) + " bytes)");

  size_t stride = strided && view.byteStride != 0 ? view.byteStride : element_size;
  if (stride < element_size)
    ctx.fail(view_where + ": byteStride " + std::to_string(stride) + " is smaller than one element (" +
             std::to_string(element_size) + " bytes)");
  if (count > 0) {
    bool fits = offset <= view.byteLength && element_size <= view.byteLength - offset &&
                (count == 1 || stride <= view.byteLength);
    // With stride <= byteLength and count < 2^28 the product cannot overflow 64 bits.
    fits = fits && (count - 1) * stride <= view.byteLength - offset - element_size;
    if (!fits)
      ctx.fail(where + ": " + std::to_string(count) + " elements of " + std::to_string(element_size) +
               " bytes at offset " + std::to_string(offset) + " run past the end of bufferView " +
               std::to_string(view_index) + " (" + std::to_string(view.byteLength) + " bytes)");
  }
  return {m.buffers[size_t(view.buffer)].data.data() + view.byteOffset + offset, count, stride};
}

// An accessor decoded to doubles: element i has components values[i * components + c].
struct AccessorValues {
  std::vector<double> values;
  size_t count = 0;
  int components = 0;
  int component_type = 0;
};

void decode_element(const uint8_t* p, int component_type, int components, bool normalized, double* out) {
  const int size = component_size(component_type);
  for (int c = 0; c < components; ++c) out[c] = read_component(p + c * size, component_type, normalized);
}

// Overwrites the elements listed in the accessor's sparse section (indices and values are tightly packed).
void apply_sparse(const Context& ctx, const tinygltf::Accessor& acc, AccessorValues& out, const std::string& where) {
  const auto& sparse = acc.sparse;
  if (sparse.count < 1 || size_t(sparse.count) > acc.count)
    ctx.fail(where + ": sparse count " + std::to_string(sparse.count) + " is not in 1.." + std::to_string(acc.count));
  if (!is_unsigned_integer(sparse.indices.componentType))
    ctx.fail(where + ": sparse indices have componentType " + std::to_string(sparse.indices.componentType) +
             " (expected an unsigned integer type)");
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) ctx.fail(where + ": negative sparse byteOffset");
  const size_t n = size_t(sparse.count);
  const size_t value_size = size_t(component_size(acc.componentType)) * size_t(out.components);
  ElementSpan indices =
      element_span(ctx, sparse.indices.bufferView, size_t(sparse.indices.byteOffset), n,
                   size_t(component_size(sparse.indices.componentType)), false, where + " sparse indices");
  ElementSpan values = element_span(ctx, sparse.values.bufferView, size_t(sparse.values.byteOffset), n, value_size,
                                    false, where + " sparse values");
  for (size_t i = 0; i < n; ++i) {
    double target = read_component(indices.data + i * indices.stride, sparse.indices.componentType, false);
    if (target >= double(acc.count))
      ctx.fail(where + ": sparse index " + std::to_string(size_t(target)) + " is not below count " +
               std::to_string(acc.count));
    decode_element(values.data + i * values.stride, acc.componentType, out.components, acc.normalized,
                   &out.values[size_t(target) * size_t(out.components)]);
  }
}

// Reads accessor `index`, which must have type `expected_type`, with sparse substitutions applied.
AccessorValues read_accessor(const Context& ctx, int index, int expected_type, const std::string& where) {
  check_index(ctx, index, ctx.model.accessors.size(), "accessor", where);
  const tinygltf::Accessor& acc = ctx.model.accessors[size_t(index)];
  const std::string at = where + " accessor " + std::to_string(index) + quoted_name(acc.name);
  const int size = component_size(acc.componentType);
  if (size == 0) ctx.fail(at + ": invalid componentType " + std::to_string(acc.componentType));
  if (acc.type != expected_type)
    ctx.fail(at + ": type is " + (component_count(acc.type) ? type_name(acc.type) : "invalid") + ", expected " +
             type_name(expected_type));
  if (acc.count > kMaxAccessorElements) ctx.fail(at + ": count " + std::to_string(acc.count) + " is too large");

  AccessorValues out;
  out.count = acc.count;
  out.components = component_count(acc.type);
  out.component_type = acc.componentType;
  const size_t element_size = size_t(size) * size_t(out.components);
  out.values.assign(acc.count * size_t(out.components), 0.0);
  if (acc.bufferView >= 0) {
    ElementSpan span = element_span(ctx, acc.bufferView, acc.byteOffset, acc.count, element_size, true, at);
    for (size_t i = 0; i < acc.count; ++i)
      decode_element(span.data + i * span.stride, acc.componentType, out.components, acc.normalized,
                     &out.values[i * size_t(out.components)]);
  } else if (!acc.sparse.isSparse) {
    ctx.fail(at + ": has neither a bufferView nor sparse data");
  }
  if (acc.sparse.isSparse) apply_sparse(ctx, acc, out, at);
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Meshes: one glTF triangle primitive becomes one candela Mesh in object space.

template <typename Vec>
std::vector<Vec> to_vectors(const AccessorValues& a) {
  std::vector<Vec> out(a.count);
  for (size_t i = 0; i < a.count; ++i)
    for (int c = 0; c < Vec::length(); ++c) out[i][c] = float(a.values[i * size_t(a.components) + size_t(c)]);
  return out;
}

template <typename Vec>
bool all_finite(const std::vector<Vec>& v) {
  for (const Vec& e : v)
    for (int c = 0; c < Vec::length(); ++c)
      if (!std::isfinite(e[c])) return false;
  return true;
}

// Reads optional attribute `name` into `out` (left empty when absent). A count different from the
// positions' is an error; non-finite values drop the attribute with a warning.
template <typename Vec>
void read_optional_attribute(const Context& ctx, const tinygltf::Primitive& prim, const char* name, int type,
                             size_t vertex_count, const std::string& where, std::vector<Vec>& out) {
  auto it = prim.attributes.find(name);
  if (it == prim.attributes.end()) return;
  std::string at = where + " " + name;
  AccessorValues a = read_accessor(ctx, it->second, type, at);
  if (a.count != vertex_count)
    ctx.fail(at + " accessor " + std::to_string(it->second) + ": count " + std::to_string(a.count) +
             " differs from POSITION count " + std::to_string(vertex_count));
  out = to_vectors<Vec>(a);
  if (!all_finite(out)) {
    ctx.warn(at + " accessor " + std::to_string(it->second) + " has NaN/Inf values; attribute dropped");
    out.clear();
  }
}

// Reads the primitive's index list (or 0..n-1 when it has none), checking every index against n.
std::vector<uint32_t> read_indices(const Context& ctx, const tinygltf::Primitive& prim, size_t vertex_count,
                                   const std::string& where) {
  std::vector<uint32_t> indices;
  if (prim.indices < 0) {
    indices.resize(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) indices[i] = uint32_t(i);
    return indices;
  }
  std::string at = where + " indices accessor " + std::to_string(prim.indices);
  AccessorValues a = read_accessor(ctx, prim.indices, TINYGLTF_TYPE_SCALAR, where + " indices");
  if (!is_unsigned_integer(a.component_type))
    ctx.fail(at + ": componentType " + std::to_string(a.component_type) + " is not an unsigned integer type");
  indices.resize(a.count);
  for (size_t i = 0; i < a.count; ++i) {
    if (a.values[i] >= double(vertex_count))
      ctx.fail(at + ": index " + std::to_string(uint64_t(a.values[i])) + " at position " + std::to_string(i) +
               " is not below the vertex count " + std::to_string(vertex_count));
    indices[i] = uint32_t(a.values[i]);
  }
  return indices;
}

// Groups indices into triangles, dropping degenerate ones (a repeated vertex or zero area).
std::vector<uvec3> assemble_triangles(const Context& ctx, const std::vector<uint32_t>& indices,
                                      const std::vector<vec3>& positions, const std::string& where) {
  if (indices.size() % 3 != 0)
    ctx.warn(where + ": " + std::to_string(indices.size()) + " indices is not a multiple of 3; the last " +
             std::to_string(indices.size() % 3) + " are ignored");
  std::vector<uvec3> triangles;
  triangles.reserve(indices.size() / 3);
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    uvec3 t(indices[i], indices[i + 1], indices[i + 2]);
    const vec3 &a = positions[t.x], &b = positions[t.y], &c = positions[t.z];
    bool repeated = t.x == t.y || t.y == t.z || t.x == t.z;
    if (repeated || glm::cross(b - a, c - a) == vec3(0.0f)) {
      ++ctx.report.degenerate_triangles_skipped;
      continue;
    }
    triangles.push_back(t);
  }
  return triangles;
}

// Converts primitive `prim_index` of glTF mesh `mesh_index`; nullopt when it is skipped (not triangles,
// or no triangle left). `default_material` is called when the primitive names no material.
template <typename DefaultMaterial>
std::optional<Mesh> convert_primitive(const Context& ctx, int mesh_index, int prim_index,
                                      DefaultMaterial&& default_material) {
  const tinygltf::Mesh& gmesh = ctx.model.meshes[size_t(mesh_index)];
  const tinygltf::Primitive& prim = gmesh.primitives[size_t(prim_index)];
  const std::string where =
      "mesh " + std::to_string(mesh_index) + quoted_name(gmesh.name) + " primitive " + std::to_string(prim_index);
  if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
    ctx.warn(where + ": mode " + std::to_string(prim.mode) + " is not TRIANGLES; primitive skipped");
    return std::nullopt;
  }
  if (!prim.targets.empty()) ctx.warn(where + ": morph targets are ignored");

  Mesh mesh;
  mesh.name = gmesh.name.empty() ? "mesh" + std::to_string(mesh_index) : gmesh.name;
  if (gmesh.primitives.size() > 1) mesh.name += "/" + std::to_string(prim_index);

  auto pos = prim.attributes.find("POSITION");
  if (pos == prim.attributes.end()) ctx.fail(where + ": has no POSITION attribute");
  mesh.positions = to_vectors<vec3>(read_accessor(ctx, pos->second, TINYGLTF_TYPE_VEC3, where + " POSITION"));
  if (!all_finite(mesh.positions))
    ctx.fail(where + " POSITION accessor " + std::to_string(pos->second) + ": contains NaN or infinite values");
  const Bounds3 bounds = mesh.bounds();
  for (const vec3& corner : {bounds.lo, bounds.hi})
    check_point(ctx, corner, where + " POSITION accessor " + std::to_string(pos->second) + ": coordinate");
  const size_t n = mesh.positions.size();  // below 2^28 (kMaxAccessorElements), so indices fit uint32

  read_optional_attribute(ctx, prim, "NORMAL", TINYGLTF_TYPE_VEC3, n, where, mesh.normals);
  read_optional_attribute(ctx, prim, "TANGENT", TINYGLTF_TYPE_VEC4, n, where, mesh.tangents);
  read_optional_attribute(ctx, prim, "TEXCOORD_0", TINYGLTF_TYPE_VEC2, n, where, mesh.uv0);
  read_optional_attribute(ctx, prim, "TEXCOORD_1", TINYGLTF_TYPE_VEC2, n, where, mesh.uv1);

  mesh.triangles = assemble_triangles(ctx, read_indices(ctx, prim, n, where), mesh.positions, where);
  if (mesh.triangles.empty()) {
    ctx.warn(where + ": no non-degenerate triangle; primitive skipped");
    return std::nullopt;
  }

  if (prim.material >= 0) {
    check_index(ctx, prim.material, ctx.model.materials.size(), "material", where);
    mesh.material = prim.material;
  } else {
    mesh.material = default_material();
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------------------
// Textures: every glTF texture becomes one candela Texture (same index); colour/data slots map to them.

enum TextureUse : uint8_t { kUnused = 0, kColor = 1, kData = 2 };

// Where a material slot that names glTF texture i points in Scene::textures (-1: no usable image).
struct TextureTable {
  std::vector<int> color, data;
};

// A textureInfo object inside a material extension: what tinygltf parses into TextureInfo for core slots.
struct ExtensionTexture {
  int index = -1;  // -1: absent or unusable
  int texcoord = 0;
  tinygltf::ExtensionMap extensions;  // KHR_texture_transform only
  std::string problem;                // why a present textureInfo was (partly) ignored
};

// Reads textureInfo `key` of extension object `ext`.
ExtensionTexture extension_texture(const Value* ext, const char* key) {
  ExtensionTexture t;
  const Value* info = ext ? member(*ext, key) : nullptr;
  if (info == nullptr) return t;
  std::optional<double> index = number(member(*info, "index"));
  if (!index || *index < 0.0 || *index > 1e9 || *index != std::floor(*index)) {
    t.problem = std::string(key) + ": index is not a non-negative integer; texture ignored";
    return t;
  }
  t.index = int(*index);
  if (const Value* tc = member(*info, "texCoord")) {
    std::optional<double> v = number(tc);
    if (v && *v >= 0.0 && *v <= 1e6 && *v == std::floor(*v))
      t.texcoord = int(*v);
    else
      t.problem = std::string(key) + ": texCoord is not a valid set index; using 0";
  }
  if (const Value* exts = member(*info, "extensions"))
    if (const Value* transform = member(*exts, "KHR_texture_transform"))
      t.extensions["KHR_texture_transform"] = *transform;
  return t;
}

// Marks each glTF texture as used for colour (sRGB) and/or data (linear), checking material references.
std::vector<uint8_t> texture_uses(const Context& ctx) {
  std::vector<uint8_t> uses(ctx.model.textures.size(), kUnused);
  auto mark = [&](int index, TextureUse use, const std::string& where) {
    if (index < 0) return;
    check_index(ctx, index, uses.size(), "texture", where);
    uses[size_t(index)] |= use;
  };
  for (size_t i = 0; i < ctx.model.materials.size(); ++i) {
    const tinygltf::Material& m = ctx.model.materials[i];
    std::string where = "material " + std::to_string(i) + quoted_name(m.name);
    mark(m.pbrMetallicRoughness.baseColorTexture.index, kColor, where + " baseColorTexture");
    mark(m.emissiveTexture.index, kColor, where + " emissiveTexture");
    mark(m.pbrMetallicRoughness.metallicRoughnessTexture.index, kData, where + " metallicRoughnessTexture");
    mark(m.normalTexture.index, kData, where + " normalTexture");
    const Value* specular = extension(m.extensions, "KHR_materials_specular");
    mark(extension_texture(specular, "specularTexture").index, kData, where + " specularTexture");
    mark(extension_texture(specular, "specularColorTexture").index, kColor, where + " specularColorTexture");
  }
  return uses;
}

Wrap to_wrap(const Context& ctx, int mode, const std::string& where) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return Wrap::Repeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Wrap::Clamp;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Wrap::Mirror;
    default: ctx.warn(where + ": unknown wrap mode " + std::to_string(mode) + "; using REPEAT"); return Wrap::Repeat;
  }
}

// Converts decoded pixels (1-4 channels, 8 or 16 bits) to 8-bit RGBA; false if they are unusable.
bool to_rgba8(const tinygltf::Image& image, std::vector<uint8_t>& rgba) {
  const int channels = image.component;
  const int bytes = image.bits == 16 ? 2 : image.bits == 8 ? 1 : 0;
  if (image.width < 1 || image.height < 1 || channels < 1 || channels > 4 || bytes == 0) return false;
  const size_t pixels = size_t(image.width) * size_t(image.height);
  if (image.image.size() < pixels * size_t(channels) * size_t(bytes)) return false;

  auto channel = [&](size_t pixel, int c) -> uint8_t {
    size_t at = (pixel * size_t(channels) + size_t(c)) * size_t(bytes);
    if (bytes == 1) return image.image[at];
    uint16_t v;
    std::memcpy(&v, &image.image[at], 2);
    return uint8_t((uint32_t(v) * 255u + 32767u) / 65535u);
  };
  rgba.resize(pixels * 4);
  for (size_t p = 0; p < pixels; ++p) {
    uint8_t* out = &rgba[p * 4];
    if (channels <= 2) {  // grey, grey + alpha
      out[0] = out[1] = out[2] = channel(p, 0);
      out[3] = channels == 2 ? channel(p, 1) : 255;
    } else {
      for (int c = 0; c < 3; ++c) out[c] = channel(p, c);
      out[3] = channels == 4 ? channel(p, 3) : 255;
    }
  }
  return true;
}

// Reads glTF texture `index` (its image and sampler); nullopt with a warning when the image is unusable.
std::optional<Texture> convert_texture(const Context& ctx, size_t index) {
  const tinygltf::Texture& gtex = ctx.model.textures[index];
  const std::string where = "texture " + std::to_string(index) + quoted_name(gtex.name);
  Texture tex;
  tex.name = gtex.name.empty() ? "texture" + std::to_string(index) : gtex.name;
  if (gtex.sampler >= 0) {
    check_index(ctx, gtex.sampler, ctx.model.samplers.size(), "sampler", where);
    const tinygltf::Sampler& s = ctx.model.samplers[size_t(gtex.sampler)];
    tex.wrap_s = to_wrap(ctx, s.wrapS, where + " wrapS");
    tex.wrap_t = to_wrap(ctx, s.wrapT, where + " wrapT");
  }
  if (gtex.source < 0 || size_t(gtex.source) >= ctx.model.images.size()) {
    ctx.warn(where + ": image " + std::to_string(gtex.source) + " does not exist; texture ignored");
    return std::nullopt;
  }
  const tinygltf::Image& image = ctx.model.images[size_t(gtex.source)];
  if (tex.name == "texture" + std::to_string(index) && !image.uri.empty()) tex.name = image.uri;
  if (!to_rgba8(image, tex.rgba)) {
    ctx.warn(where + ": image " + std::to_string(gtex.source) +
             quoted_name(image.uri.empty() ? image.name : image.uri) +
             " is missing or could not be decoded; texture ignored");
    return std::nullopt;
  }
  tex.width = image.width;
  tex.height = image.height;
  return tex;
}

// Decodes images stored in bufferViews (GLB, embedded) after checking their byte range; failures warn.
void decode_embedded_images(const Context& ctx, tinygltf::Model& model) {
  for (size_t i = 0; i < model.images.size(); ++i) {
    tinygltf::Image& image = model.images[i];
    if (image.bufferView < 0 || !image.image.empty()) continue;
    std::string where = "image " + std::to_string(i) + quoted_name(image.name);
    check_index(ctx, image.bufferView, model.bufferViews.size(), "bufferView", where);  // before reading its length
    size_t length = model.bufferViews[size_t(image.bufferView)].byteLength;
    ElementSpan bytes = element_span(ctx, image.bufferView, 0, 1, length, false, where);
    std::string err, warn;
    if (length == 0 || length > size_t(INT32_MAX) ||
        !tinygltf::LoadImageData(&image, int(i), &err, &warn, 0, 0, bytes.data, int(length), nullptr)) {
      image.image.clear();
      ctx.warn(where + ": could not be decoded: " + one_line(err));
    }
  }
}

// Reads model.textures and writes scene.textures; a texture used both as colour and as data gets a
// linear copy appended at the end. Returns the slot table materials use.
TextureTable convert_textures(const Context& ctx, Scene& scene) {
  const std::vector<uint8_t> uses = texture_uses(ctx);
  const size_t count = ctx.model.textures.size();
  TextureTable table{std::vector<int>(count, -1), std::vector<int>(count, -1)};
  std::vector<size_t> need_linear_copy;
  for (size_t i = 0; i < count; ++i) {
    std::optional<Texture> tex = convert_texture(ctx, i);
    if (!tex) {  // placeholder keeps the indices aligned with the file; no slot points at it
      Texture placeholder;
      placeholder.name = "missing texture " + std::to_string(i);
      placeholder.width = placeholder.height = 1;
      placeholder.rgba = {255, 255, 255, 255};
      scene.textures.push_back(std::move(placeholder));
      continue;
    }
    tex->srgb = (uses[i] & kColor) != 0;
    table.color[i] = int(i);
    table.data[i] = int(i);
    if ((uses[i] & kColor) && (uses[i] & kData)) need_linear_copy.push_back(i);
    scene.textures.push_back(std::move(*tex));
  }
  for (size_t i : need_linear_copy) {
    Texture copy = scene.textures[i];
    copy.srgb = false;
    copy.name += " (linear)";
    table.data[i] = int(scene.textures.size());
    scene.textures.push_back(std::move(copy));
  }
  return table;
}

// ---------------------------------------------------------------------------------------------------
// Materials.

// `value` clamped to [lo, hi]; a warning when it had to change, `fallback` when it is not finite.
float clamped(const Context& ctx, double value, float lo, float hi, float fallback, const std::string& what) {
  if (!std::isfinite(value)) {
    ctx.warn(what + " is not finite; using " + format_number(fallback));
    return fallback;
  }
  if (value < lo || value > hi) {
    float c = float(std::clamp(value, double(lo), double(hi)));
    ctx.warn(what + " = " + format_number(value) + " is out of range; clamped to " + format_number(c));
    return c;
  }
  return float(value);
}

// Applies KHR_texture_transform (offset, scale, rotation, texCoord override) to `ref`.
void read_texture_transform(const Context& ctx, const tinygltf::ExtensionMap& extensions, TextureRef& ref,
                            const std::string& where) {
  const Value* ext = extension(extensions, "KHR_texture_transform");
  if (ext == nullptr) return;
  const std::string at = where + " KHR_texture_transform";
  if (const Value* v = member(*ext, "offset")) {
    if (auto o = numbers(v, 2))
      ref.offset = vec2(float((*o)[0]), float((*o)[1]));
    else
      ctx.warn(at + ": offset is not two finite numbers; ignored");
  }
  if (const Value* v = member(*ext, "scale")) {
    if (auto s = numbers(v, 2))
      ref.scale = vec2(float((*s)[0]), float((*s)[1]));
    else
      ctx.warn(at + ": scale is not two finite numbers; ignored");
  }
  if (const Value* v = member(*ext, "rotation")) {
    auto r = number(v);
    if (r && std::isfinite(*r))
      ref.rotation = float(*r);
    else
      ctx.warn(at + ": rotation is not a finite number; ignored");
  }
  if (const Value* v = member(*ext, "texCoord")) {
    auto t = number(v);
    if (t && *t >= 0.0 && *t <= 1e6)
      ref.texcoord = int(*t);
    else
      ctx.warn(at + ": texCoord is not a valid set index; ignored");
  }
}

// A material slot: glTF texture `index` through the colour or data table, its UV set and transform.
TextureRef texture_ref(const Context& ctx, const TextureTable& table, int index, int texcoord,
                       const tinygltf::ExtensionMap& extensions, bool color, const std::string& where) {
  TextureRef ref;
  if (index < 0) return ref;  // no texture; indices were range-checked by texture_uses
  ref.texture = color ? table.color[size_t(index)] : table.data[size_t(index)];
  ref.texcoord = texcoord;
  read_texture_transform(ctx, extensions, ref, where);
  if (ref.texcoord < 0 || ref.texcoord > 1) {
    ctx.warn(where + ": TEXCOORD_" + std::to_string(ref.texcoord) + " is not supported; using TEXCOORD_0");
    ref.texcoord = 0;
  }
  return ref;
}

// Reads emissiveFactor and KHR_materials_emissive_strength; values above 1 are legal and kept.
vec3 read_emission(const Context& ctx, const tinygltf::Material& m, const std::string& where) {
  vec3 emission(0.0f);
  if (m.emissiveFactor.size() == 3) {
    for (int c = 0; c < 3; ++c)
      emission[c] = clamped(ctx, m.emissiveFactor[size_t(c)], 0.0f, kInfinity, 0.0f,
                            where + " emissiveFactor[" + std::to_string(c) + "]");
  } else if (!m.emissiveFactor.empty()) {
    ctx.warn(where + ": emissiveFactor does not have 3 components; ignored");
  }
  if (const Value* ext = extension(m.extensions, "KHR_materials_emissive_strength")) {
    if (auto s = number(member(*ext, "emissiveStrength")))
      emission *= clamped(ctx, *s, 0.0f, kInfinity, 1.0f, where + " emissiveStrength");
  }
  return emission;
}

// KHR_materials_specular (factor, colour, their textures) and KHR_materials_ior into `mat`.
void read_specular(const Context& ctx, const TextureTable& table, const tinygltf::Material& m, const std::string& where,
                   Material& mat) {
  if (const Value* ext = extension(m.extensions, "KHR_materials_specular")) {
    const std::string at = where + " KHR_materials_specular";
    if (std::optional<double> f = number(member(*ext, "specularFactor")))
      mat.specular = clamped(ctx, *f, 0.0f, 1.0f, 1.0f, at + " specularFactor");
    if (const Value* c = member(*ext, "specularColorFactor")) {
      if (auto rgb = numbers(c, 3))
        for (int k = 0; k < 3; ++k)
          mat.specular_color[k] = clamped(ctx, (*rgb)[size_t(k)], 0.0f, 1e6f, 1.0f, at + " specularColorFactor");
      else
        ctx.warn(at + ": specularColorFactor is not three finite numbers; using white");
    }
    for (bool color : {false, true}) {
      const char* key = color ? "specularColorTexture" : "specularTexture";
      ExtensionTexture t = extension_texture(ext, key);
      if (!t.problem.empty()) ctx.warn(at + " " + t.problem);
      (color ? mat.specular_color_tex : mat.specular_tex) =
          texture_ref(ctx, table, t.index, t.texcoord, t.extensions, color, at + " " + key);
    }
  }
  if (const Value* ext = extension(m.extensions, "KHR_materials_ior")) {
    std::optional<double> ior = number(member(*ext, "ior"));
    // The schema allows ior >= 1, or exactly 0 (F0 = 1).
    if (ior && std::isfinite(*ior) && (*ior == 0.0 || (*ior >= 1.0 && *ior <= 1e6)))
      mat.ior = float(*ior);
    else if (ior)
      ctx.warn(where + " KHR_materials_ior: ior must be 0 or at least 1; using 1.5");
  }
}

AlphaMode to_alpha_mode(const Context& ctx, const std::string& mode, const std::string& where) {
  if (mode == "OPAQUE" || mode.empty()) return AlphaMode::Opaque;
  if (mode == "MASK") return AlphaMode::Mask;
  if (mode == "BLEND") return AlphaMode::Blend;
  ctx.warn(where + ": unknown alphaMode '" + mode + "'; using OPAQUE");
  return AlphaMode::Opaque;
}

// Reads glTF material `index` into a candela Material, clamping out-of-range factors with a warning.
Material convert_material(const Context& ctx, const TextureTable& table, size_t index) {
  const tinygltf::Material& m = ctx.model.materials[index];
  const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
  const std::string where = "material " + std::to_string(index) + quoted_name(m.name);
  Material mat;
  mat.name = m.name.empty() ? "material" + std::to_string(index) : m.name;

  if (pbr.baseColorFactor.size() == 4) {
    for (int c = 0; c < 4; ++c)
      mat.base_color[c] = clamped(ctx, pbr.baseColorFactor[size_t(c)], 0.0f, 1.0f, 1.0f,
                                  where + " baseColorFactor[" + std::to_string(c) + "]");
  } else {
    ctx.warn(where + ": baseColorFactor does not have 4 components; using white");
  }
  mat.metallic = clamped(ctx, pbr.metallicFactor, 0.0f, 1.0f, 1.0f, where + " metallicFactor");
  mat.roughness = clamped(ctx, pbr.roughnessFactor, 0.0f, 1.0f, 1.0f, where + " roughnessFactor");
  mat.emission = read_emission(ctx, m, where);

  const auto& bc = pbr.baseColorTexture;
  const auto& mr = pbr.metallicRoughnessTexture;
  mat.base_color_tex = texture_ref(ctx, table, bc.index, bc.texCoord, bc.extensions, true, where + " baseColorTexture");
  mat.metallic_roughness_tex =
      texture_ref(ctx, table, mr.index, mr.texCoord, mr.extensions, false, where + " metallicRoughnessTexture");
  mat.normal_tex = texture_ref(ctx, table, m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions,
                               false, where + " normalTexture");
  mat.emissive_tex = texture_ref(ctx, table, m.emissiveTexture.index, m.emissiveTexture.texCoord,
                                 m.emissiveTexture.extensions, true, where + " emissiveTexture");
  if (std::isfinite(m.normalTexture.scale))
    mat.normal_scale = float(m.normalTexture.scale);
  else
    ctx.warn(where + ": normalTexture scale is not finite; using 1");

  read_specular(ctx, table, m, where, mat);
  mat.alpha_mode = to_alpha_mode(ctx, m.alphaMode, where);
  mat.alpha_cutoff = clamped(ctx, m.alphaCutoff, 0.0f, kInfinity, 0.5f, where + " alphaCutoff");
  mat.double_sided = m.doubleSided;
  return mat;
}

// ---------------------------------------------------------------------------------------------------
// Node hierarchy: local transforms and the depth-first walk from the scene's roots.

// The node's local matrix: `matrix` (column-major) if given, else translation * rotation * scale.
mat4 local_matrix(const Context& ctx, const tinygltf::Node& node, const std::string& where) {
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!finite(node.matrix) || !finite(node.translation) || !finite(node.rotation) || !finite(node.scale))
    ctx.fail(where + ": transform contains NaN or infinite values");
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) ctx.fail(where + ": matrix does not have 16 elements");
    mat4 m;
    for (int col = 0; col < 4; ++col)
      for (int row = 0; row < 4; ++row) m[col][row] = float(node.matrix[size_t(col * 4 + row)]);
    return m;
  }
  if (!node.translation.empty() && node.translation.size() != 3)
    ctx.fail(where + ": translation does not have 3 elements");
  if (!node.rotation.empty() && node.rotation.size() != 4) ctx.fail(where + ": rotation does not have 4 elements");
  if (!node.scale.empty() && node.scale.size() != 3) ctx.fail(where + ": scale does not have 3 elements");

  mat4 m(1.0f);
  if (!node.translation.empty())
    m = glm::translate(m, vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2])));
  if (!node.rotation.empty()) {
    const auto& r = node.rotation;                                    // glTF order x, y, z, w
    glm::quat q{float(r[3]), float(r[0]), float(r[1]), float(r[2])};  // glm order w, x, y, z
    if (glm::length(q) > 0.0f)
      m *= glm::mat4_cast(glm::normalize(q));
    else
      ctx.warn(where + ": rotation is a zero quaternion; ignored");
  }
  if (!node.scale.empty()) m = glm::scale(m, vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
  return m;
}

struct PlacedNode {
  int node = 0;
  mat4 world{1.0f};
  mat4 parent_world{1.0f};
};

// The scene's root nodes: those of the default scene or, when the file names none, every node that is
// nobody's child.
std::vector<int> root_nodes(const Context& ctx) {
  const tinygltf::Model& m = ctx.model;
  if (m.defaultScene >= 0) {
    check_index(ctx, m.defaultScene, m.scenes.size(), "scene", "default scene");
    return m.scenes[size_t(m.defaultScene)].nodes;
  }
  std::vector<bool> is_child(m.nodes.size(), false);
  for (size_t i = 0; i < m.nodes.size(); ++i)
    for (int child : m.nodes[i].children) {
      check_index(ctx, child, m.nodes.size(), "node", "node " + std::to_string(i) + " children");
      is_child[size_t(child)] = true;
    }
  std::vector<int> roots;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(int(i));
  return roots;
}

// Walks the hierarchy depth-first (children in file order) and returns every node with its world
// matrix. A node reached twice (a cycle or a shared child) is an error.
std::vector<PlacedNode> place_nodes(const Context& ctx) {
  const tinygltf::Model& m = ctx.model;
  std::vector<PlacedNode> placed;
  std::vector<bool> visited(m.nodes.size(), false);
  std::vector<PlacedNode> stack;
  std::vector<int> roots = root_nodes(ctx);
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, mat4(1.0f)});
  while (!stack.empty()) {
    PlacedNode top = stack.back();
    stack.pop_back();
    check_index(ctx, top.node, m.nodes.size(), "node", "scene hierarchy");
    const std::string where = "node " + std::to_string(top.node) + quoted_name(m.nodes[size_t(top.node)].name);
    if (visited[size_t(top.node)]) ctx.fail(where + ": reached twice in the hierarchy (cycle or shared child)");
    visited[size_t(top.node)] = true;
    const tinygltf::Node& node = m.nodes[size_t(top.node)];
    top.parent_world = top.world;
    top.world = top.world * local_matrix(ctx, node, where);
    placed.push_back(top);
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, top.world});
  }
  return placed;
}

// ---------------------------------------------------------------------------------------------------
// Lights and camera placed through the hierarchy.

// Reads the KHR_lights_punctual light a node carries (if any) in world space.
std::optional<PunctualLight> node_light(const Context& ctx, const PlacedNode& placed, const std::string& where) {
  const tinygltf::Node& node = ctx.model.nodes[size_t(placed.node)];
  const Value* ext = extension(node.extensions, "KHR_lights_punctual");
  if (ext == nullptr) return std::nullopt;
  auto index = number(member(*ext, "light"));
  if (!index) ctx.fail(where + ": KHR_lights_punctual has no light index");
  if (*index < 0 || *index >= double(ctx.model.lights.size()) || *index != std::floor(*index))
    ctx.fail(where + ": KHR_lights_punctual light " + format_number(*index) + " does not exist (the file has " +
             std::to_string(ctx.model.lights.size()) + ")");
  const tinygltf::Light& gl = ctx.model.lights[size_t(*index)];
  const std::string at = where + " light " + std::to_string(size_t(*index)) + quoted_name(gl.name);

  PunctualLight light;
  if (gl.type == "point")
    light.type = PunctualType::Point;
  else if (gl.type == "spot")
    light.type = PunctualType::Spot;
  else if (gl.type == "directional")
    light.type = PunctualType::Directional;
  else {
    ctx.warn(at + ": unknown type '" + gl.type + "'; light ignored");
    return std::nullopt;
  }
  vec3 color(1.0f);
  if (gl.color.size() == 3) {
    for (int c = 0; c < 3; ++c)
      color[c] = clamped(ctx, gl.color[size_t(c)], 0.0f, kInfinity, 1.0f, at + " color[" + std::to_string(c) + "]");
  } else if (!gl.color.empty()) {
    ctx.warn(at + ": color does not have 3 components; using white");
  }
  light.intensity = color * clamped(ctx, gl.intensity, 0.0f, kInfinity, 1.0f, at + " intensity");
  check_magnitude(ctx, max_component(light.intensity), kMaxEmission, at + ": intensity x color");

  light.position = vec3(placed.world * vec4(0.0f, 0.0f, 0.0f, 1.0f));
  check_point(ctx, light.position, at + ": world-space position");
  vec3 dir(placed.world * vec4(0.0f, 0.0f, -1.0f, 0.0f));
  if (glm::length(dir) > 0.0f && is_finite(glm::normalize(dir)))
    light.direction = glm::normalize(dir);
  else
    ctx.warn(at + ": node transform collapses the light direction; using -Z");

  if (light.type == PunctualType::Spot) {
    light.outer_cone = clamped(ctx, gl.spot.outerConeAngle, 0.0f, kPi / 2.0f, kPi / 4.0f, at + " outerConeAngle");
    light.inner_cone = clamped(ctx, gl.spot.innerConeAngle, 0.0f, light.outer_cone, 0.0f, at + " innerConeAngle");
  }
  light.instance = -1;
  return light;
}

// Reads the camera a node carries, if it is perspective (orthographic ones are ignored with a warning).
std::optional<CameraDesc> node_camera(const Context& ctx, const PlacedNode& placed, const std::string& where) {
  const tinygltf::Node& node = ctx.model.nodes[size_t(placed.node)];
  if (node.camera < 0) return std::nullopt;
  check_index(ctx, node.camera, ctx.model.cameras.size(), "camera", where);
  const tinygltf::Camera& cam = ctx.model.cameras[size_t(node.camera)];
  if (cam.type != "perspective") {
    ctx.warn(where + ": camera " + std::to_string(node.camera) + " is " + cam.type + "; ignored");
    return std::nullopt;
  }
  CameraDesc desc;
  desc.position = vec3(placed.world * vec4(0.0f, 0.0f, 0.0f, 1.0f));
  check_point(ctx, desc.position, where + ": camera position");
  vec3 forward(placed.world * vec4(0.0f, 0.0f, -1.0f, 0.0f));
  vec3 up(placed.world * vec4(0.0f, 1.0f, 0.0f, 0.0f));
  if (!(glm::length(forward) > 0.0f) || !(glm::length(up) > 0.0f)) {
    ctx.warn(where + ": camera transform is degenerate; camera ignored");
    return std::nullopt;
  }
  desc.target = desc.position + glm::normalize(forward);
  desc.up = glm::normalize(up);
  const double yfov = cam.perspective.yfov;
  if (std::isfinite(yfov) && yfov > 0.0 && yfov < double(kPi))
    desc.vfov_degrees = float(glm::degrees(yfov));
  else
    ctx.warn(where + ": camera yfov " + std::to_string(yfov) + " is not in (0, pi); using 45 degrees");
  return desc;
}

// ---------------------------------------------------------------------------------------------------
// The whole conversion.

// Reads the placed nodes and writes meshes (once per glTF mesh/primitive), instances, lights and camera.
// Returns, per glTF node, the instances it carries (one per primitive), for animations.
std::vector<std::vector<int>> convert_nodes(const Context& ctx, const std::vector<PlacedNode>& placed_nodes,
                                            Scene& scene) {
  std::vector<std::vector<int>> instances_of(ctx.model.nodes.size());
  std::map<std::pair<int, int>, int> mesh_of;  // (glTF mesh, primitive) -> candela mesh, -1 = skipped
  std::vector<Bounds3> mesh_bounds;            // per candela mesh (this function alone adds meshes), object space
  CHECK(scene.meshes.empty());
  int default_material = -1;
  auto get_default_material = [&]() {
    if (default_material < 0) {
      default_material = int(scene.materials.size());
      Material m;
      m.name = "default";
      scene.materials.push_back(m);
    }
    return default_material;
  };

  for (const PlacedNode& placed : placed_nodes) {
    const tinygltf::Node& node = ctx.model.nodes[size_t(placed.node)];
    const std::string where = "node " + std::to_string(placed.node) + quoted_name(node.name);
    if (node.mesh >= 0) {
      check_index(ctx, node.mesh, ctx.model.meshes.size(), "mesh", where);
      const size_t primitives = ctx.model.meshes[size_t(node.mesh)].primitives.size();
      for (size_t p = 0; p < primitives; ++p) {
        auto key = std::make_pair(node.mesh, int(p));
        auto it = mesh_of.find(key);
        if (it == mesh_of.end()) {
          std::optional<Mesh> mesh = convert_primitive(ctx, node.mesh, int(p), get_default_material);
          int id = -1;
          if (mesh) {
            id = int(scene.meshes.size());
            mesh_bounds.push_back(mesh->bounds());
            scene.meshes.push_back(std::move(*mesh));
          }
          it = mesh_of.emplace(key, id).first;
        }
        if (it->second < 0) continue;
        check_placed_bounds(ctx, mesh_bounds[size_t(it->second)], placed.world, where);
        Instance inst;
        inst.mesh = it->second;
        inst.transform = inst.prev_transform = placed.world;
        inst.animated = false;
        inst.name = node.name;
        instances_of[size_t(placed.node)].push_back(int(scene.instances.size()));
        scene.instances.push_back(inst);
      }
    }
    if (std::optional<PunctualLight> light = node_light(ctx, placed, where)) scene.punctual_lights.push_back(*light);
    if (!scene.camera) scene.camera = node_camera(ctx, placed, where);
  }
  return instances_of;
}

// ---------------------------------------------------------------------------------------------------
// Animations: translation, rotation and scale channels of nodes that carry meshes.

// One sampler's keys: times (strictly increasing, finite) and `components` values per key. CUBICSPLINE
// keeps each key's value (the middle of its in-tangent, value, out-tangent triple), interpolated linearly.
template <class T>
Track<T> read_channel_track(const Context& ctx, const tinygltf::Animation& anim, const tinygltf::AnimationChannel& ch,
                            int type, const std::string& where) {
  check_index(ctx, ch.sampler, anim.samplers.size(), "sampler", where);
  const tinygltf::AnimationSampler& sampler = anim.samplers[size_t(ch.sampler)];
  AccessorValues times = read_accessor(ctx, sampler.input, TINYGLTF_TYPE_SCALAR, where + " input");
  AccessorValues values = read_accessor(ctx, sampler.output, type, where + " output");
  Track<T> track;
  size_t per_key = 1, offset = 0;
  if (sampler.interpolation == "STEP") {
    track.interpolation = Interpolation::Step;
  } else if (sampler.interpolation == "CUBICSPLINE") {
    ctx.warn(where + ": CUBICSPLINE interpolation is read as LINEAR through the keys' values (tangents ignored)");
    per_key = 3;
    offset = 1;
  } else if (sampler.interpolation != "LINEAR" && !sampler.interpolation.empty()) {
    ctx.fail(where + ": unknown interpolation '" + sampler.interpolation + "'");
  }
  if (times.count == 0) ctx.fail(where + ": input accessor has no keys");
  if (values.count != times.count * per_key)
    ctx.fail(where + ": output has " + std::to_string(values.count) + " values for " + std::to_string(times.count) +
             " keys (expected " + std::to_string(times.count * per_key) + ")");
  for (size_t i = 0; i < times.count; ++i) {
    double t = times.values[i];
    if (!std::isfinite(t) || (i > 0 && t <= times.values[i - 1]))
      ctx.fail(where + ": key time " + format_number(t) + " (key " + std::to_string(i) +
               ") is not finite and increasing");
    const double* v = &values.values[(i * per_key + offset) * size_t(values.components)];
    for (int c = 0; c < values.components; ++c)
      if (!std::isfinite(v[c])) ctx.fail(where + ": key " + std::to_string(i) + " has a NaN or infinite value");
    track.times.push_back(float(t));
    if constexpr (std::is_same_v<T, quat>) {
      quat q{float(v[3]), float(v[0]), float(v[1]), float(v[2])};  // glTF x, y, z, w -> glm w, x, y, z
      if (glm::length(q) == 0.0f) ctx.fail(where + ": key " + std::to_string(i) + " is a zero quaternion");
      track.values.push_back(glm::normalize(q));
    } else {
      track.values.push_back(vec3(float(v[0]), float(v[1]), float(v[2])));
    }
  }
  return track;
}

// Throws unless the animated instance stays within the coordinate limit at every key time of its tracks
// (between keys translation and scale interpolate between key values, and rotation keeps lengths).
void check_animated_bounds(const Context& ctx, const InstanceAnimation& a, const Bounds3& object,
                           const std::string& where) {
  for (const std::vector<float>* times : {&a.translation.times, &a.rotation.times, &a.scale.times})
    for (float t : *times)
      check_placed_bounds(ctx, object, a.transform_at(t), where + " at animation time " + format_number(t));
}

// Throws unless every material's emission (emissiveFactor x strength) is within the emission limit.
void check_emission(const Context& ctx, const Scene& scene) {
  for (size_t i = 0; i < ctx.model.materials.size(); ++i)
    check_magnitude(ctx, max_component(scene.materials[i].emission), kMaxEmission,
                    "material " + std::to_string(i) + quoted_name(ctx.model.materials[i].name) + ": emission");
}

// Reads every animation's node channels into Scene::instance_animations (all animations play at once,
// from time 0 in seconds). A node's instance moves as parent_world * T(t) * R(t) * S(t), unanimated
// channels keeping the node's own values. Nodes without meshes, nodes with a `matrix`, nodes below an
// animated node, morph weights and lights or cameras on animated nodes are reported and left static.
void convert_animations(const Context& ctx, const std::vector<PlacedNode>& placed_nodes,
                        const std::vector<std::vector<int>>& instances_of, Scene& scene) {
  const tinygltf::Model& m = ctx.model;
  if (m.animations.empty()) return;
  std::map<int, InstanceAnimation> by_node;
  for (size_t a = 0; a < m.animations.size(); ++a) {
    const tinygltf::Animation& anim = m.animations[a];
    for (size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& ch = anim.channels[c];
      const std::string where =
          "animation " + std::to_string(a) + quoted_name(anim.name) + " channel " + std::to_string(c);
      if (ch.target_node < 0) continue;  // the spec allows targets defined by extensions only
      check_index(ctx, ch.target_node, m.nodes.size(), "node", where);
      const tinygltf::Node& node = m.nodes[size_t(ch.target_node)];
      const std::string node_where = where + " (node " + std::to_string(ch.target_node) + quoted_name(node.name) + ")";
      if (ch.target_path == "weights") {
        ctx.warn(node_where + ": morph target weights are ignored");
        continue;
      }
      if (!node.matrix.empty()) {
        ctx.fail(node_where + ": animates a node that has a matrix (glTF forbids this)");
      }
      InstanceAnimation& anim_of_node = by_node[ch.target_node];
      if (ch.target_path == "translation")
        anim_of_node.translation = read_channel_track<vec3>(ctx, anim, ch, TINYGLTF_TYPE_VEC3, node_where);
      else if (ch.target_path == "rotation")
        anim_of_node.rotation = read_channel_track<quat>(ctx, anim, ch, TINYGLTF_TYPE_VEC4, node_where);
      else if (ch.target_path == "scale")
        anim_of_node.scale = read_channel_track<vec3>(ctx, anim, ch, TINYGLTF_TYPE_VEC3, node_where);
      else
        ctx.fail(node_where + ": unknown target path '" + ch.target_path + "'");
    }
  }
  std::vector<int> parent(m.nodes.size(), -1);
  for (size_t i = 0; i < m.nodes.size(); ++i)
    for (int child : m.nodes[i].children) parent[size_t(child)] = int(i);
  auto constant = [](auto value) {
    Track<decltype(value)> t;
    t.times = {0.0f};
    t.values = {value};
    return t;
  };
  for (const PlacedNode& placed : placed_nodes) {
    const tinygltf::Node& node = m.nodes[size_t(placed.node)];
    const std::string where = "node " + std::to_string(placed.node) + quoted_name(node.name);
    for (int up = parent[size_t(placed.node)]; up >= 0; up = parent[size_t(up)])
      if (by_node.count(up) && !instances_of[size_t(placed.node)].empty()) {
        ctx.warn(where + ": only its ancestor node " + std::to_string(up) +
                 " is animated; it stays in its static pose");
        break;
      }
    auto it = by_node.find(placed.node);
    if (it == by_node.end()) continue;
    if (instances_of[size_t(placed.node)].empty()) {
      ctx.warn(where + ": animated but carries no mesh; ignored");
      continue;
    }
    if (node.camera >= 0 || node.extensions.count("KHR_lights_punctual"))
      ctx.warn(where + ": its light or camera does not follow the animation");
    InstanceAnimation a = it->second;
    a.after = placed.parent_world;
    if (a.translation.empty() && !node.translation.empty())
      a.translation =
          constant(vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2])));
    if (a.rotation.empty() && !node.rotation.empty())
      a.rotation = constant(glm::normalize(
          quat(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]), float(node.rotation[2]))));
    if (a.scale.empty() && !node.scale.empty())
      a.scale = constant(vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
    for (int instance : instances_of[size_t(placed.node)]) {
      a.instance = instance;
      check_animated_bounds(ctx, a, scene.meshes[size_t(scene.instances[size_t(instance)].mesh)].bounds(), where);
      scene.instances[size_t(instance)].animated = true;
      scene.instance_animations.push_back(a);
    }
  }
}

Scene convert(const std::string& path, LoadReport& report) {
  // Parse the file (tinygltf) and decode images embedded in buffers.
  tinygltf::Model model;
  {
    const tinygltf::Model empty;
    Context reading{path, empty, report};
    model = read_model(reading);
    Context decoding{path, model, report};
    decode_embedded_images(decoding, model);
  }
  const Context ctx{path, model, report};
  check_required_extensions(ctx);

  Scene scene;
  scene.name = std::filesystem::path(path).stem().string();
  // Textures first (materials refer to them), then materials, then the node hierarchy.
  TextureTable table = convert_textures(ctx, scene);
  for (size_t i = 0; i < model.materials.size(); ++i) scene.materials.push_back(convert_material(ctx, table, i));
  const std::vector<PlacedNode> placed = place_nodes(ctx);
  convert_animations(ctx, placed, convert_nodes(ctx, placed, scene), scene);
  check_emission(ctx, scene);
  if (scene.instances.empty()) ctx.warn("the scene has no triangle mesh");
  return scene;
}

}  // namespace

Scene load_gltf(const std::string& path, LoadReport* report) {
  LoadReport local;
  LoadReport& rep = report ? *report : local;
  rep = LoadReport{};
  try {
    return convert(path, rep);
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw InputError(path + ": out of memory while loading (corrupt or too large file)");
  } catch (const std::exception& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace candela
