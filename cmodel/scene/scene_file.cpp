#include "scene/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "common/input_file.hpp"
#include "scene/mesh.hpp"
#include "scene/procedural.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A JSON value and its JSON pointer (RFC 6901), for messages.
struct Node {
  const Json* value;
  std::string pointer;

  const Json& operator*() const { return *value; }
  const Json* operator->() const { return value; }
};

std::string escape_pointer_token(std::string_view key) {
  std::string out;
  for (const char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  // Pointers are for messages: a huge key is quoted in part (quote_input).
  return quote_input(out);
}

std::string describe(const Json& j) {
  if (j.is_array()) return fmt::format("an array of {}", j.size());
  if (j.is_object()) return "an object";
  if (j.is_string()) return fmt::format("the string {}", j.dump());
  if (j.is_boolean()) return j.dump();
  if (j.is_null()) return "null";
  return fmt::format("the number {}", j.dump());
}

// Turns the scene file's JSON into values, naming the file and the JSON pointer of
// any value it rejects, with what was expected.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const Node& n, std::string_view what) const {
    throw Error(fmt::format("{}: {}: {}", file_, n.pointer.empty() ? "/" : n.pointer, what));
  }
  [[noreturn]] void expected(const Node& n, std::string_view what) const {
    fail(n, fmt::format("expected {}, got {}", what, describe(*n)));
  }

  void require_object(const Node& n) const {
    if (!n->is_object()) expected(n, "an object");
  }
  // `n` must be an object whose keys are all in `allowed`.
  void allow_keys(const Node& n, std::initializer_list<std::string_view> allowed) const {
    require_object(n);
    for (const auto& [key, value] : n->items()) {
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        fail(child_node(n, key),
             fmt::format("unknown key \"{}\" (expected one of: {})", quote_input(key), fmt::join(allowed, ", ")));
      }
    }
  }
  static Node child_node(const Node& n, std::string_view key) {
    return {&(*n.value)[std::string(key)], n.pointer + "/" + escape_pointer_token(key)};
  }
  static std::optional<Node> find(const Node& n, std::string_view key) {
    if (!n->contains(key)) return std::nullopt;
    return child_node(n, key);
  }
  Node get(const Node& n, std::string_view key) const {
    if (!n->contains(key)) fail(n, fmt::format("missing key \"{}\"", key));
    return child_node(n, key);
  }
  std::vector<Node> elements(const Node& n) const {
    if (!n->is_array()) expected(n, "an array");
    std::vector<Node> out;
    for (std::size_t i = 0; i < n->size(); ++i) {
      out.push_back({&(*n.value)[i], fmt::format("{}/{}", n.pointer, i)});
    }
    return out;
  }

  double number(const Node& n) const {
    if (!n->is_number()) expected(n, "a number");
    return n->get<double>();
  }
  double number_at_least(const Node& n, double lo) const {
    const double v = number(n);
    if (!(v >= lo)) fail(n, fmt::format("expected a number >= {}, got {}", lo, v));
    return v;
  }
  double fraction(const Node& n) const {
    const double v = number(n);
    if (!(v >= 0.0 && v <= 1.0)) fail(n, fmt::format("expected a number in [0, 1], got {}", v));
    return v;
  }
  std::string string(const Node& n) const {
    if (!n->is_string() || n->get_ref<const std::string&>().empty()) {
      expected(n, "a non-empty string");
    }
    return n->get<std::string>();
  }
  bool boolean(const Node& n) const {
    if (!n->is_boolean()) expected(n, "true or false");
    return n->get<bool>();
  }
  glm::dvec3 vec3(const Node& n) const {
    if (!n->is_array() || n->size() != 3 ||
        !std::all_of(n->begin(), n->end(), [](const Json& e) { return e.is_number(); })) {
      expected(n, "an array of 3 numbers");
    }
    return {(*n)[0].get<double>(), (*n)[1].get<double>(), (*n)[2].get<double>()};
  }
  glm::dvec3 color(const Node& n) const {
    const glm::dvec3 c = vec3(n);
    if (c.x < 0.0 || c.y < 0.0 || c.z < 0.0) {
      fail(n, "expected an array of 3 numbers >= 0 (linear RGB)");
    }
    return c;
  }
  glm::dvec3 nonzero_vec3(const Node& n) const {
    const glm::dvec3 v = vec3(n);
    if (glm::dot(v, v) == 0.0) fail(n, "expected a non-zero vector, got [0, 0, 0]");
    return v;
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

std::string read_text(const fs::path& path) {
  return read_input_file(path, "the scene file", kMaxSceneFileBytes);
}

// nlohmann keeps the last of two equal keys; a scene file with both is ambiguous. A first
// pass over the file's events (SAX, no document built) finds them, with the JSON pointer
// that names them, and refuses nesting no scene needs before the document is built: a
// callback on nlohmann's own parser would do the same in time quadratic in an array's
// length (its end_object rescans the parent container) and memory that grows with depth.
class KeyTracker : public nlohmann::json_sax<Json> {
 public:
  // A scene file nests 5 deep (/meshes/0/transform/rotate/0); this bounds the first
  // pass's memory and the document's.
  static constexpr std::size_t kMaxDepth = 32;

  explicit KeyTracker(const std::string& file) : file_(file) {}

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(true); }
  bool start_array(std::size_t) override { return open(false); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t& k) override {
    Frame& f = frames_.back();
    f.key = k;
    if (!f.keys.insert(k).second) {
      throw Error(fmt::format("{}: {}: duplicate key \"{}\" (the keys of an object must be unique)", file_, pointer(),
                              quote_input(k)));
    }
    return true;
  }
  // The document parse that follows reports the error with its position.
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;       // object: the key being read
    std::size_t next = 0;  // array: the index of the next element
  };

  bool value() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().next;
    return true;
  }
  bool open(bool object) {
    value();
    if (frames_.size() == kMaxDepth) {
      throw Error(fmt::format("{}: {}: nested deeper than {} levels; a scene file needs 5", file_, pointer(), kMaxDepth));
    }
    frames_.push_back({object, {}, {}});
    return true;
  }
  bool close() {
    frames_.pop_back();
    return true;
  }
  std::string pointer() const {
    std::string out;
    for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
      out += '/';
      out += frames_[i].object ? escape_pointer_token(frames_[i].key) : std::to_string(frames_[i].next - 1);
    }
    return out.empty() ? std::string("/") : out;
  }

  const std::string& file_;
  std::vector<Frame> frames_;
};

// nlohmann reports the byte offset just past the offending character; editors want
// line:column (both from 1).
Json parse_json(const std::string& text, const std::string& file) {
  // nlohmann stops at a NUL byte and accepts the document before it: bytes after it,
  // a truncated or binary file, would be ignored unseen.
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos) {
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n');
    const std::size_t line_start = text.rfind('\n', nul);
    const std::size_t column = line_start == std::string::npos ? nul + 1 : nul - line_start;
    throw Error(fmt::format("{}:{}:{}: malformed JSON: a NUL byte (byte {} of {}); a scene file is UTF-8 text", file,
                            line, column, nul, text.size()));
  }
  try {
    KeyTracker tracker(file);
    Json::sax_parse(text, &tracker);
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    const std::size_t at = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    const std::size_t line = 1 + static_cast<std::size_t>(
                                     std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    const std::size_t last_newline = text.rfind('\n', at == 0 ? 0 : at - 1);
    const std::size_t column =
        (last_newline == std::string::npos || last_newline >= at) ? at + 1 : at - last_newline;
    // Keep nlohmann's explanation, without its own "[json.exception...] ... column N: " prefix.
    std::string_view why = e.what();
    if (const std::size_t p = why.find("column "); p != std::string_view::npos) {
      if (const std::size_t q = why.find(": ", p); q != std::string_view::npos) {
        why.remove_prefix(q + 2);
      }
    }
    throw Error(fmt::format("{}:{}:{}: malformed JSON: {}", file, line, column, why));
  } catch (const Json::exception& e) {
    // A number beyond double's range is an out_of_range error without a position
    // (found by fuzzing); the message quotes the number, which is enough to find it.
    std::string_view why = e.what();
    if (const std::size_t p = why.find("] "); p != std::string_view::npos) why.remove_prefix(p + 2);
    throw Error(fmt::format("{}: malformed JSON: {}", file, why));
  }
}

Camera read_camera(const Reader& r, const Node& n) {
  r.allow_keys(n, {"position", "look_at", "up", "vfov", "aperture_radius", "focus_distance"});
  Camera c;
  c.position = r.vec3(r.get(n, "position"));
  const Node look_at = r.get(n, "look_at");
  c.look_at = r.vec3(look_at);
  if (c.look_at == c.position) r.fail(look_at, "the camera looks at its own position");
  if (const auto up = Reader::find(n, "up")) {
    c.up = r.nonzero_vec3(*up);
    const glm::dvec3 view = glm::normalize(c.look_at - c.position);
    if (glm::length(glm::cross(view, glm::normalize(c.up))) < 1e-9) {
      r.fail(*up, "up is parallel to the view direction");
    }
  }
  if (const auto vfov = Reader::find(n, "vfov")) {
    c.vfov_degrees = r.number(*vfov);
    if (!(c.vfov_degrees > 0.0 && c.vfov_degrees < 180.0)) {
      r.fail(*vfov, fmt::format("expected degrees in (0, 180), got {}", c.vfov_degrees));
    }
  }
  if (const auto a = Reader::find(n, "aperture_radius")) c.aperture_radius = r.number_at_least(*a, 0.0);
  if (const auto f = Reader::find(n, "focus_distance")) c.focus_distance = r.number_at_least(*f, 0.0);
  return c;
}

Light read_light(const Reader& r, const Node& n) {
  r.require_object(n);
  const Node type = r.get(n, "type");
  const std::string kind = r.string(type);
  Light l;
  if (kind == "point") {
    r.allow_keys(n, {"type", "color", "position"});
    l.kind = LightKind::kPoint;
    l.position = r.vec3(r.get(n, "position"));
  } else if (kind == "directional") {
    r.allow_keys(n, {"type", "color", "direction"});
    l.kind = LightKind::kDirectional;
    l.direction = glm::normalize(r.nonzero_vec3(r.get(n, "direction")));
  } else if (kind == "area") {
    r.allow_keys(n, {"type", "color", "corner", "edge_u", "edge_v"});
    l.kind = LightKind::kArea;
    l.position = r.vec3(r.get(n, "corner"));
    l.edge_u = r.nonzero_vec3(r.get(n, "edge_u"));
    const Node edge_v = r.get(n, "edge_v");
    l.edge_v = r.nonzero_vec3(edge_v);
    if (glm::length(glm::cross(glm::normalize(l.edge_u), glm::normalize(l.edge_v))) < 1e-9) {
      r.fail(edge_v, "edge_v is parallel to edge_u (the light has no area)");
    }
  } else {
    r.fail(type, fmt::format("expected \"point\", \"directional\" or \"area\", got \"{}\"", kind));
  }
  if (const auto c = Reader::find(n, "color")) l.color = r.color(*c);
  return l;
}

Material read_material(const Reader& r, const Node& n) {
  r.allow_keys(n, {"name", "ambient", "diffuse", "specular", "shininess", "reflectance",
                   "transmittance", "ior", "roughness", "shader"});
  Material m;
  m.name = r.string(r.get(n, "name"));
  if (const auto v = Reader::find(n, "ambient")) m.ambient = r.color(*v);
  if (const auto v = Reader::find(n, "diffuse")) m.diffuse = r.color(*v);
  if (const auto v = Reader::find(n, "specular")) m.specular = r.color(*v);
  if (const auto v = Reader::find(n, "shininess")) m.shininess = r.number_at_least(*v, 0.0);
  if (const auto v = Reader::find(n, "reflectance")) m.reflectance = r.fraction(*v);
  if (const auto v = Reader::find(n, "transmittance")) m.transmittance = r.fraction(*v);
  if (const auto v = Reader::find(n, "ior")) {
    m.ior = r.number(*v);
    if (!(m.ior > 0.0)) r.fail(*v, fmt::format("expected an index of refraction > 0, got {}", m.ior));
  }
  if (const auto v = Reader::find(n, "roughness")) m.roughness = r.fraction(*v);
  if (const auto v = Reader::find(n, "shader")) m.shader = r.string(*v);
  return m;
}

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

glm::dmat4 read_rotation(const Reader& r, const Node& n) {
  r.require_object(n);
  if (n->contains("euler")) {
    r.allow_keys(n, {"euler"});
    const glm::dvec3 e = r.vec3(Reader::child_node(n, "euler"));
    // Degrees about x, then y, then z (world axes).
    glm::dmat4 m(1.0);
    m = glm::rotate(m, radians(e.z), glm::dvec3(0.0, 0.0, 1.0));
    m = glm::rotate(m, radians(e.y), glm::dvec3(0.0, 1.0, 0.0));
    return glm::rotate(m, radians(e.x), glm::dvec3(1.0, 0.0, 0.0));
  }
  r.allow_keys(n, {"axis", "degrees"});
  const glm::dvec3 axis = glm::normalize(r.nonzero_vec3(r.get(n, "axis")));
  return glm::rotate(glm::dmat4(1.0), radians(r.number(r.get(n, "degrees"))), axis);
}

glm::dmat4 read_transform(const Reader& r, const Node& n) {
  if (n->is_array()) {
    // Row-major, as written: [[m00, m01, m02, tx], ..., [0, 0, 0, 1]].
    const auto rows = r.elements(n);
    if (rows.size() != 4) r.expected(n, "an array of 4 rows of 4 numbers");
    glm::dmat4 m;
    for (int row = 0; row < 4; ++row) {
      const Node& rn = rows[static_cast<std::size_t>(row)];
      if (!rn->is_array() || rn->size() != 4 ||
          !std::all_of(rn->begin(), rn->end(), [](const Json& e) { return e.is_number(); })) {
        r.expected(rn, "an array of 4 numbers");
      }
      for (int col = 0; col < 4; ++col) m[col][row] = (*rn)[static_cast<std::size_t>(col)].get<double>();
    }
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
      r.fail(rows[3], "expected the last row [0, 0, 0, 1] (affine transforms only)");
    }
    return m;
  }
  r.allow_keys(n, {"translate", "rotate", "scale"});
  glm::dmat4 m(1.0);
  if (const auto t = Reader::find(n, "translate")) m = glm::translate(m, r.vec3(*t));
  if (const auto rot = Reader::find(n, "rotate")) m = m * read_rotation(r, *rot);
  if (const auto s = Reader::find(n, "scale")) {
    glm::dvec3 k;
    if ((*s)->is_number()) {
      k = glm::dvec3(r.number(*s));
    } else if ((*s)->is_array()) {
      k = r.vec3(*s);
    } else {
      r.expected(*s, "a number or an array of 3 numbers");
    }
    if (k.x == 0.0 || k.y == 0.0 || k.z == 0.0) r.fail(*s, "expected non-zero scale factors");
    m = glm::scale(m, k);
  }
  return m;
}

std::uint32_t find_material(const Scene& s, const std::string& name) {
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    if (s.materials[i].name == name) return static_cast<std::uint32_t>(i);
  }
  return static_cast<std::uint32_t>(s.materials.size());
}

std::string material_names(const Scene& s) {
  std::vector<std::string> names;
  for (const Material& m : s.materials) names.push_back(m.name);
  return names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "));
}

Scene read_procedural(const Reader& r, const Node& n) {
  r.allow_keys(n, {"generator", "size"});
  const Node generator = r.get(n, "generator");
  const std::string name = r.string(generator);
  if (!is_builtin_scene(name) || name.find(':') != std::string::npos) {
    r.fail(generator, fmt::format("unknown generator \"{}\" (expected one of: {})", name,
                                  fmt::join(builtin_scene_names(), ", ")));
  }
  std::string spec = name;
  Node where = generator;
  if (const auto size = Reader::find(n, "size")) {
    if (!(*size)->is_number_integer()) r.expected(*size, "a whole number");
    spec += fmt::format(":{}", (*size)->get<long long>());
    where = *size;
  }
  try {
    return make_builtin_scene(spec);
  } catch (const Error& e) {
    r.fail(where, e.what());
  }
}

}  // namespace

Material default_material() {
  Material m;
  m.name = "default";
  m.ambient = glm::dvec3(0.1);
  m.diffuse = glm::dvec3(0.7);
  m.specular = glm::dvec3(0.2);
  m.shininess = 32.0;
  return m;
}

Camera frame_bounds(const Bounds& box) {
  Camera c;
  c.vfov_degrees = 40.0;
  const glm::dvec3 center = box.empty() ? glm::dvec3(0.0) : 0.5 * (box.lo + box.hi);
  double radius = box.empty() ? 0.0 : 0.5 * glm::length(box.hi - box.lo);
  if (!(radius > 0.0)) radius = 1.0;
  // The bounding sphere fits the vertical field of view, with 5% to spare.
  const double distance = 1.05 * radius / std::sin(radians(c.vfov_degrees / 2.0));
  c.look_at = center;
  c.position = center + distance * glm::normalize(glm::dvec3(0.6, 0.5, 1.0));
  c.up = {0.0, 1.0, 0.0};
  return c;
}

Light light_near(const Camera& camera, const Bounds& box) {
  // Relative to the scene's own size only, so that a scene scaled by 2^k lights the same.
  double radius = box.empty() ? 0.0 : 0.5 * glm::length(box.hi - box.lo);
  if (!(radius > 0.0)) radius = 1.0;
  const glm::dvec3 view = glm::normalize(camera.look_at - camera.position);
  const glm::dvec3 right = glm::normalize(glm::cross(view, camera.up));
  Light l;
  l.kind = LightKind::kPoint;
  l.position = camera.position + 0.5 * radius * (glm::normalize(camera.up) + right);
  return l;
}

Scene load_scene_file(const fs::path& path) {
  return parse_scene_json(read_text(path), path.parent_path(), path.string());
}

Scene parse_scene_json(std::string_view text, const fs::path& base_dir, const std::string& source) {
  const std::string& file = source;
  const Json root = parse_json(std::string(text), file);
  const Reader r(file);
  const Node top{&root, ""};
  r.allow_keys(top, {"comment", "camera", "background", "lights", "materials", "meshes",
                     "procedural"});

  Scene s;
  const auto procedural = Reader::find(top, "procedural");
  if (procedural) s = read_procedural(r, *procedural);
  s.source = file;

  // File materials replace a generator's material of the same name, so a scene file
  // can restyle a built-in scene; otherwise names must be unique.
  const std::size_t generated = s.materials.size();
  if (const auto materials = Reader::find(top, "materials")) {
    for (const Node& n : r.elements(*materials)) {
      Material m = read_material(r, n);
      const std::uint32_t at = find_material(s, m.name);
      if (at < generated) {
        s.materials[at] = std::move(m);
      } else if (at < s.materials.size()) {
        r.fail(Reader::child_node(n, "name"), fmt::format("duplicate material \"{}\"", m.name));
      } else {
        s.materials.push_back(std::move(m));
      }
    }
  }

  if (const auto meshes = Reader::find(top, "meshes")) {
    for (const Node& n : r.elements(*meshes)) {
      r.allow_keys(n, {"file", "material", "transform", "smooth"});
      MeshOptions options;
      if (const auto m = Reader::find(n, "material")) {
        const std::string name = r.string(*m);
        options.material_id = find_material(s, name);
        if (options.material_id == s.materials.size()) {
          r.fail(*m, fmt::format("unknown material \"{}\" (defined: {})", name, material_names(s)));
        }
      } else {
        options.material_id = find_material(s, "default");
        if (options.material_id == s.materials.size()) s.materials.push_back(default_material());
      }
      if (const auto t = Reader::find(n, "transform")) options.transform = read_transform(r, *t);
      if (const auto sm = Reader::find(n, "smooth")) options.smooth = r.boolean(*sm);
      const Node file_node = r.get(n, "file");
      const std::string reference = r.string(file_node);
      try {
        append_geometry(s, load_mesh(resolve_mesh_path(reference, base_dir), options));
      } catch (const Error& e) {
        r.fail(file_node, e.what());
      }
    }
  }
  if (s.triangles.empty()) {
    throw Error(fmt::format("{}: the scene has no triangles (give \"meshes\" or \"procedural\")",
                            file));
  }

  const Bounds box = scene_bounds(s);
  if (const auto camera = Reader::find(top, "camera")) {
    s.camera = read_camera(r, *camera);
  } else if (!procedural) {
    s.camera = frame_bounds(box);
  }
  if (const auto lights = Reader::find(top, "lights")) {
    s.lights.clear();
    for (const Node& n : r.elements(*lights)) s.lights.push_back(read_light(r, n));
  } else if (!procedural) {
    s.lights = {light_near(s.camera, box)};
  }
  if (const auto background = Reader::find(top, "background")) s.background = r.color(*background);
  return s;
}

Scene load_bare_mesh(const fs::path& path) {
  Scene s;
  s.source = path.string();
  s.materials.push_back(default_material());
  append_geometry(s, load_mesh(path, MeshOptions{}));
  if (s.triangles.empty()) throw Error(fmt::format("{}: the mesh has no triangles", path.string()));
  const Bounds box = scene_bounds(s);
  s.camera = frame_bounds(box);
  s.lights = {light_near(s.camera, box)};
  return s;
}

}  // namespace rpu
