#include "scene/mesh_check.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <assimp/ParsingUtils.h>
#include <assimp/fast_atof.h>
#include <fmt/format.h>

#include "common/error.hpp"

namespace rpu {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, std::string_view what) {
  throw Error(fmt::format("{}: {}", path.string(), what));
}

// What fast_atof.h's parsers throw here, for a string that is not a number: the library
// does not export the constructor of their default, DeadlyImportError.
class NotANumber : public std::runtime_error {
 public:
  template <typename... Parts>
  explicit NotANumber(Parts&&... parts) : std::runtime_error((std::string() + ... + std::string(parts))) {}
};

// The word at `p`, for a message: up to the next space or line end, at most 32 characters.
std::string word_at(const char* p) {
  std::string word;
  while (word.size() < 32 && !Assimp::IsSpaceOrNewLine(*p)) word += *p++;
  return fmt::format("\"{}\"", word);
}

// Assimp's strtoul10 and strtol10 (fast_atof.h), wrapping in 32 bits as they do, without
// their signed overflow.
std::uint32_t strtoul10(const char*& p) {
  std::uint32_t value = 0;
  while (*p >= '0' && *p <= '9') value = value * 10u + static_cast<std::uint32_t>(*p++ - '0');
  return value;
}
std::int32_t strtol10(const char*& p) {
  const bool negative = *p == '-';
  if (negative || *p == '+') ++p;
  const std::uint32_t magnitude = strtoul10(p);
  return static_cast<std::int32_t>(negative ? 0u - magnitude : magnitude);
}

// Takes `count` instances of at least `least_bytes` each out of `bytes_left` (plus `slack`
// for a last line without its line end), or fails with "the header promises 1000000000
// vertices, but the 23 bytes after the header can hold at most 3 (each takes at least 6
// bytes)".
void check_count(const fs::path& path, std::uint64_t count, std::string_view what,
                 std::uint64_t least_bytes, std::uint64_t slack, std::uint64_t& bytes_left,
                 std::string_view where) {
  const std::uint64_t most = (bytes_left + slack) / least_bytes;
  if (count > most) {
    fail(path, fmt::format("the header promises {} {}, but the {} bytes {} can hold at most {} "
                           "(each takes at least {} bytes): the file is truncated or its header "
                           "is wrong",
                           count, what, bytes_left, where, most, least_bytes));
  }
  bytes_left -= std::min(bytes_left, count * least_bytes);
}

// The 1-based number of the line that `at` (a pointer into `text`) is on.
std::size_t line_at(const std::string& text, const char* at) {
  return 1 + static_cast<std::size_t>(std::count(text.c_str(), at, '\n'));
}

// --- OFF -------------------------------------------------------------------------------
// Assimp's OFF reader (OFFLoader.cpp, 5.2) allocates the header's vertex and face counts
// up front, then reads one line per vertex and per face.

// OFFLoader.cpp's NextToken: spaces and line ends, then whole comment lines.
void off_next_token(const char*& p, const char* end) {
  Assimp::SkipSpacesAndLineEnd(&p);
  while (p < end && (*p == '#' || *p == '\n' || *p == '\r')) {
    Assimp::SkipLine(&p);
    Assimp::SkipSpacesAndLineEnd(&p);
  }
}

void check_off(const fs::path& path, const std::string& text) {
  const char* p = text.c_str();
  const char* const end = p + text.size();
  // OFFLoader.cpp's bounds, against its buffer of the file plus a terminating zero.
  const auto left = [&] { return static_cast<std::size_t>(end - p); };
  // The header as OFFLoader.cpp parses it: optional ST, C, N, 4 and n prefixes to "OFF"
  // (keeping them when "OFF" is missing), then dimension, vertex and face counts.
  bool uvs = false, colors = false, normals = false, homogeneous = false, dimension = false;
  unsigned dimensions = 3;
  off_next_token(p, end);
  if (left() > 1 && p[0] == 'S' && p[1] == 'T') uvs = true, p += 2;
  if (left() > 0 && p[0] == 'C') colors = true, ++p;
  if (left() > 0 && p[0] == 'N') normals = true, ++p;
  if (left() > 0 && p[0] == '4') homogeneous = true, ++p;
  if (left() > 0 && p[0] == 'n') dimension = true, ++p;
  if (left() > 2 && p[0] == 'O' && p[1] == 'F' && p[2] == 'F') {
    p += 3;
    off_next_token(p, end);
  } else {
    homogeneous = false;
    off_next_token(p, end);
    if (left() == 0 || *p < '0' || *p > '9') return;  // Assimp rejects the header
  }
  if (dimension) {
    dimensions = strtoul10(p);
    off_next_token(p, end);
  }
  if (dimensions > 3) return;  // Assimp rejects it
  off_next_token(p, end);
  const std::uint32_t vertices = strtoul10(p);
  off_next_token(p, end);
  const std::uint32_t faces = strtoul10(p);
  off_next_token(p, end);
  strtoul10(p);  // edges, unused
  off_next_token(p, end);
  // A vertex line holds its numbers, each a digit and a separator; a face line at least
  // "1 0" and a line end. The last line may lack its line end: one byte of slack.
  const unsigned numbers = dimensions + (homogeneous ? 1u : 0u) + (normals ? 3u : 0u) +
                           (colors ? 1u : 0u) + (uvs ? 2u : 0u);
  std::uint64_t bytes_left = left();
  check_count(path, vertices, "vertices", std::max(2u, 2u * numbers), 1, bytes_left,
              "after the header");
  check_count(path, faces, "faces", 4, 1, bytes_left, "left after the vertex lines");

  // The vertex and face lines, read as OFFLoader.cpp reads them (GetNextLine into a
  // 4096-byte line, which it overruns by one byte for a longer line). It skips a face of
  // 0 or more than 9 corners and takes one off the mesh's face count for it, so that
  // enough of them wrap the count around; such a face is refused here.
  std::array<char, 4097> line{};
  const char* line_start = p;
  const auto read_line = [&] {
    line_start = p;
    const bool read = Assimp::GetNextLine(p, line.data());
    if (read && std::strlen(line.data()) >= 4096) {
      fail(path, fmt::format("line {} is longer than Assimp's 4095 characters", line_at(text, line_start)));
    }
    return read;
  };
  for (std::uint32_t v = 0; v < vertices && read_line(); ++v) {
  }
  for (std::uint32_t f = 0; f < faces && read_line(); ++f) {
    const char* q = line.data();
    Assimp::SkipSpaces(&q);
    const std::uint32_t corners = strtoul10(q);
    if (corners == 0 || corners > 9) {
      fail(path, fmt::format("line {}: face {} has {} corners; Assimp 5.2 reads OFF faces of 1 to 9",
                             line_at(text, line_start), f, corners));
    }
  }
}

// --- STL -------------------------------------------------------------------------------
// Assimp's STL reader (STLLoader.cpp, 5.2) takes a file as binary when 84 + 50 x count
// equals its size (32-bit), else as ascii when it starts with "solid". Its ascii reader
// keeps the meshes it builds outside the scene until the end, so every error it throws
// leaks them: the ascii text is walked here first, with its steps, and refused where it
// would throw.

bool is_binary_stl(const char* p, std::size_t size) {
  if (size < 84) return false;
  std::uint32_t count = 0;
  std::memcpy(&count, p + 80, sizeof count);
  return count * 50u + 84u == size;
}

// STLLoader.cpp's IsAsciiSTL. (It also looks for a char above 127 in the first 500,
// which finds none where char is signed, as on x86.)
bool is_ascii_stl(const char* p, std::size_t size) {
  if (is_binary_stl(p, size)) return false;
  const char* const end = p + size;
  return Assimp::SkipSpaces(&p) && p + 5 < end && std::strncmp(p, "solid", 5) == 0;
}

// STLImporter::LoadASCIIFile's walk over `text` (the file plus a terminating zero).
void walk_ascii_stl(const fs::path& path, const std::string& text) {
  const char* p = text.c_str();
  const char* const end = p + text.size();
  const auto number = [&](const char* q, const char* what) {
    try {
      float value = 0.0f;
      return Assimp::fast_atoreal_move<float, NotANumber>(q, value);
    } catch (const NotANumber&) {
      fail(path, fmt::format("offset {}: {} {} is not a number", q - text.c_str(), what, word_at(q)));
    }
  };
  const auto three_numbers = [&](const char*& q, const char* what) {
    for (int k = 0; k < 3; ++k) {
      Assimp::SkipSpaces(&q);
      q = number(q, what);
    }
  };
  for (unsigned solid = 0; is_ascii_stl(p, static_cast<std::size_t>(end - p)); ++solid) {
    Assimp::SkipSpaces(&p);
    p += 5;
    Assimp::SkipSpaces(&p);
    const char* const name = p;
    while (!Assimp::IsSpaceOrNewLine(*p)) ++p;
    if (p - name >= static_cast<std::ptrdiff_t>(MAXLEN)) {
      fail(path, fmt::format("offset {}: the solid's name is longer than Assimp's {} characters",
                             name - text.c_str(), MAXLEN - 1));
    }
    std::size_t positions = 0, normals = 0;
    unsigned corners = 3;
    for (;;) {
      if (!Assimp::SkipSpacesAndLineEnd(&p)) break;
      if (std::strncmp(p, "facet", 5) == 0 && Assimp::IsSpaceOrNewLine(p[5]) && p[5] != '\0') {
        corners = 0;
        p += 6;
        Assimp::SkipSpaces(&p);
        if (std::strncmp(p, "normal", 6) == 0) {
          if (p[6] == '\0') fail(path, "the file ends inside a facet");
          p += 7;
          three_numbers(p, "facet normal");
          normals += 3;
        }
      } else if (std::strncmp(p, "vertex", 6) == 0 && Assimp::IsSpaceOrNewLine(p[6])) {
        if (corners >= 3) {
          ++p;
        } else {
          if (p[6] == '\0') fail(path, "the file ends inside a facet");
          p += 7;
          three_numbers(p, "vertex");
          ++positions;
          ++corners;
        }
      } else if (std::strncmp(p, "endsolid", 8) == 0) {
        do ++p;
        while (!Assimp::IsLineEnd(*p));
        Assimp::SkipSpacesAndLineEnd(&p);
        break;
      } else {
        do ++p;
        while (!Assimp::IsSpaceOrNewLine(*p));
      }
    }
    if (positions % 3 != 0) {
      fail(path, fmt::format("solid {} has {} vertices, not three per facet", solid, positions));
    }
    if (normals != positions) {
      fail(path, fmt::format("solid {} has {} facet normals for {} facets", solid, normals / 3, positions / 3));
    }
  }
}

void check_stl(const fs::path& path, const std::string& bytes) {
  if (is_binary_stl(bytes.data(), bytes.size())) return;  // Assimp checks the count itself
  if (is_ascii_stl(bytes.c_str(), bytes.size())) {
    walk_ascii_stl(path, bytes);
    return;
  }
  // Not ascii, so binary to Assimp: a count that disagrees with the size is a truncated
  // file or a lying header.
  if (bytes.size() < 84) return;
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, sizeof count);  // little endian, as Assimp reads it
  fail(path, fmt::format("the binary STL header promises {} triangles (84 + 50 x {} = {} bytes), "
                         "but the file has {} bytes: it is truncated or its header is wrong",
                         count, count, 84 + 50 * std::uint64_t{count}, bytes.size()));
}

// --- Polygons ----------------------------------------------------------------------------
// Assimp's Triangulate clips ears in time quadratic in a polygon's corners: one
// non-convex polygon of 65,536 corners took 33 s, one of 2 million would take hours. The
// squared corners of a file's polygons (of more than four) are capped at about 8 s of it.
constexpr std::uint64_t kMaxTriangulationWork = std::uint64_t{1} << 30;

class TriangulationWork {
 public:
  explicit TriangulationWork(const fs::path& path) : path_(path) {}
  // `where` names the polygon, called only when it is refused.
  template <typename Where>
  void add(std::uint64_t corners, const Where& where) {
    if (corners <= 4) return;
    largest_ = std::max(largest_, corners);
    work_ += std::min(corners, kMaxTriangulationWork) * std::min(corners, kMaxTriangulationWork);
    if (work_ > kMaxTriangulationWork) {
      fail(path_, fmt::format("{}: the polygons up to here (the largest of {} corners) would take Assimp's "
                              "triangulation more than {} steps (corners squared, summed); split them "
                              "into smaller polygons or triangles",
                              where(), largest_, kMaxTriangulationWork));
    }
  }

 private:
  const fs::path& path_;
  std::uint64_t work_ = 0, largest_ = 0;
};

// --- OBJ -------------------------------------------------------------------------------
// Assimp's OBJ reader (ObjFileImporter.cpp, 5.2) counts a line statement of n vertices as
// n - 1 segments but copies all n vertices, so a line of one vertex makes it throw ("no
// vertices", "bad vertex index") with the meshes it has built not yet in the scene: they
// leak. Such a statement is refused here; vertices are counted as ObjFileParser::getFace
// counts them (atoi, stepping by the digits of the value read), on lines joined at a
// trailing backslash as its reader joins them.
void check_obj(const fs::path& path, const std::string& text) {
  TriangulationWork polygons(path);
  std::size_t line = 1;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t start_line = line;
    std::string statement;
    for (; at < text.size() && text[at] != '\n'; ++at) {
      if (text[at] == '\\' && (text.compare(at + 1, 1, "\n") == 0 || text.compare(at + 1, 2, "\r\n") == 0)) {
        at = text.find('\n', at);
        ++line;
        statement += ' ';
        continue;
      }
      statement += text[at];
    }
    ++at;
    ++line;
    if (!statement.empty() && statement[0] == 'f') {
      std::uint64_t corners = 0;
      for (std::size_t k = statement.find_first_of(" \t"); k < statement.size();) {
        const std::size_t begin = statement.find_first_not_of(" \t\r", k);
        if (begin == std::string::npos) break;
        ++corners;
        k = statement.find_first_of(" \t", begin);
      }
      polygons.add(corners, [&] { return fmt::format("line {}", start_line); });
    }
    if (statement.empty() || statement[0] != 'l') continue;
    const char* p = statement.c_str();
    // Assimp's step (the digits of the int that atoi made of a longer number) can go
    // past the statement's end; it reads on into its buffer, this stops at the end.
    const char* const end = p + statement.size();
    while (*p != '\0' && !Assimp::IsSpaceOrNewLine(*p)) ++p;  // the keyword
    unsigned vertices = 0;
    int slot = 0;
    while (*p != '\0' && !Assimp::IsLineEnd(*p)) {
      int step = 1;
      if (*p == '/') {
        ++slot;
      } else if (Assimp::IsSpace(*p)) {
        slot = 0;
      } else {
        const long value = std::strtol(p, nullptr, 10);
        const int v = static_cast<int>(value);  // as glibc's atoi
        if (v < 0) ++step;
        for (int rest = v; (rest /= 10) != 0;) ++step;
        if (slot == 0 && v != 0) ++vertices;
      }
      p += std::min<std::ptrdiff_t>(step, end - p);
    }
    if (vertices == 1) {
      fail(path, fmt::format("line {}: a line statement with one vertex (Assimp 5.2 fails on it "
                             "and leaks what it has read; give two or more)",
                             start_line));
    }
  }
}

// --- PLY -------------------------------------------------------------------------------
// Assimp's PLY reader (PlyLoader.cpp, PlyParser.cpp, 5.2) reads the header line by line
// into one reused buffer, resizing it without clearing it, so a line shorter than an
// earlier one is followed by the earlier one's tail; after a comment it goes on parsing in
// that tail. It allocates an element's declared count up front and resizes each list to
// its length before reading the items; in binary files it reads past the end of the file
// into padding. So the header is parsed here with Assimp's own steps on the same buffer,
// and the data is walked with the counts and list lengths Assimp will act on.

enum class PlyType { kInvalid, kChar, kUChar, kShort, kUShort, kInt, kUInt, kFloat, kDouble };

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::kChar:
    case PlyType::kUChar: return 1;
    case PlyType::kShort:
    case PlyType::kUShort: return 2;
    case PlyType::kInt:
    case PlyType::kUInt:
    case PlyType::kFloat: return 4;
    case PlyType::kDouble: return 8;
    case PlyType::kInvalid: break;
  }
  return 0;
}

struct PlyProperty {
  bool list = false;
  PlyType count_type = PlyType::kInvalid;
  PlyType type = PlyType::kInvalid;
};

enum class PlySemantic { kInvalid, kVertex, kFace, kTriStrip, kEdge, kMaterial, kTextureFile };

struct PlyElement {
  std::string name;
  PlySemantic semantic = PlySemantic::kInvalid;
  std::uint32_t count = 0;
  std::vector<PlyProperty> properties;
};

// IOStreamBuffer::getNextLine over the file's bytes: the line goes to the front of
// `buffer` (resized to the cache size, never cleared) followed by '\n'. Returns false at
// the end of the file, as Assimp does, also after a last line without a line end.
class PlyLines {
 public:
  PlyLines(const fs::path& path, const std::string& bytes)
      : path_(path), bytes_(bytes), cache_size_(std::min<std::size_t>(bytes.size(), kCache)) {}

  bool next(std::string& buffer) {
    buffer.resize(cache_size_);
    if (pos_ >= bytes_.size()) return false;
    if (Assimp::IsLineEnd(bytes_[pos_])) {
      // Assimp skips to the next '\n' here, without a bound: only the line ends "\n"
      // and "\r\n" are followed here, anything else is refused.
      if (bytes_[pos_] == '\r' && pos_ + 1 < bytes_.size() && bytes_[pos_ + 1] == '\n') ++pos_;
      if (bytes_[pos_] != '\n') {
        fail(path_, fmt::format("line {}: a stray control byte 0x{:02x} (PLY lines end with \\n "
                                "or \\r\\n)",
                                line_at(pos_), static_cast<unsigned char>(bytes_[pos_])));
      }
      if (++pos_ >= bytes_.size()) return false;
    }
    line_start_ = pos_;
    std::size_t i = 0;
    while (!Assimp::IsLineEnd(bytes_[pos_])) {
      buffer[i++] = bytes_[pos_++];
      if (i == buffer.size()) buffer.resize(buffer.size() * 2);
      if (pos_ >= bytes_.size()) return false;
    }
    buffer[i] = '\n';
    line_length_ = i;
    ++pos_;
    return true;
  }

  std::size_t pos() const { return pos_; }
  std::size_t line_length() const { return line_length_; }
  std::size_t line() const { return line_at(line_start_); }
  std::size_t line_at(std::size_t offset) const {
    return 1 + static_cast<std::size_t>(std::count(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
  }
  static constexpr std::size_t kCache = 1024 * 1024;  // PlyLoader.cpp's IOStreamBuffer

 private:
  const fs::path& path_;
  const std::string& bytes_;
  std::size_t cache_size_;
  std::size_t pos_ = 0;
  std::size_t line_start_ = 0;
  std::size_t line_length_ = 0;
};

// PLY::DOM's helpers: Assimp's parsing step at the front of the buffer, then the consumed
// characters erased.
template <typename Step>
bool at_front(std::string& buffer, Step step) {
  if (buffer.empty()) return false;
  const char* const begin = buffer.c_str();
  const char* p = begin;
  const bool ok = step(p);
  buffer.erase(0, static_cast<std::size_t>(p - begin));
  return ok;
}
bool skip_spaces(std::string& b) {
  return at_front(b, [](const char*& p) { return Assimp::SkipSpaces(&p); });
}
bool skip_line(std::string& b) {
  return at_front(b, [](const char*& p) { return Assimp::SkipLine(&p); });
}
bool skip_spaces_and_line_end(std::string& b) {
  return at_front(b, [](const char*& p) { return Assimp::SkipSpacesAndLineEnd(&p); });
}
bool token_match(std::string& b, const char* token) {
  return at_front(b, [token](const char*& p) {
    return Assimp::TokenMatch(p, token, static_cast<unsigned>(std::strlen(token)));
  });
}

// PLY::DOM::SkipComments.
void skip_comments(std::string& buffer) {
  std::string rest = buffer;
  if (!skip_spaces(rest) || !token_match(rest, "comment")) return;
  if (!skip_spaces(rest)) skip_line(rest);
  if (!token_match(rest, "TextureFile")) {
    skip_line(rest);
    buffer = std::move(rest);
  }
}

// PLY::Property::ParseDataType, in its order of tries.
PlyType parse_type(std::string& b) {
  struct Name {
    const char* token;
    PlyType type;
  };
  static constexpr std::array<Name, 16> kNames{{
      {"char", PlyType::kChar},       {"int8", PlyType::kChar},       {"uchar", PlyType::kUChar},
      {"uint8", PlyType::kUChar},     {"short", PlyType::kShort},     {"int16", PlyType::kShort},
      {"ushort", PlyType::kUShort},   {"uint16", PlyType::kUShort},   {"int32", PlyType::kInt},
      {"int", PlyType::kInt},         {"uint32", PlyType::kUInt},     {"uint", PlyType::kUInt},
      {"float", PlyType::kFloat},     {"float32", PlyType::kFloat},   {"double64", PlyType::kDouble},
      {"double", PlyType::kDouble},
  }};
  for (const Name& n : kNames) {
    if (token_match(b, n.token)) return n.type;
  }
  return token_match(b, "float64") ? PlyType::kDouble : PlyType::kInvalid;
}

// PLY::Property::ParseSemantic, for what it consumes: the first name that matches, or the
// rest of the line.
void skip_property_name(std::string& b) {
  static constexpr std::array kNames{
      "red",           "green",          "blue",           "alpha",         "vertex_index",
      "vertex_indices", "texcoord",      "material_index", "ambient_red",   "ambient_green",
      "ambient_blue",  "ambient_alpha",  "diffuse_red",    "diffuse_green", "diffuse_blue",
      "diffuse_alpha", "specular_red",   "specular_green", "specular_blue", "specular_alpha",
      "opacity",       "specular_power", "r",              "g",             "b",
      "u",             "s",              "tx",             "texture_u",     "v",
      "t",             "ty",             "texture_v",      "x",             "y",
      "z",             "nx",             "ny",             "nz"};
  for (const char* name : kNames) {
    if (token_match(b, name)) return;
  }
  skip_line(b);
}

// PLY::Property::ParseProperty.
bool parse_property(std::string& b, PlyProperty& out) {
  if (!skip_spaces(b) || !token_match(b, "property") || !skip_spaces(b)) return false;
  if (token_match(b, "list")) {
    out.list = true;
    if ((out.count_type = parse_type(b)) == PlyType::kInvalid) return skip_line(b), false;
    if (!skip_spaces(b)) return false;
  }
  if ((out.type = parse_type(b)) == PlyType::kInvalid) return skip_line(b), false;
  if (!skip_spaces(b)) return false;
  skip_property_name(b);
  skip_spaces_and_line_end(b);
  return true;
}

// PLY::Element::ParseElement: "element NAME COUNT", then its property lines.
bool parse_element(PlyLines& lines, std::string& b, PlyElement& out, const fs::path& path) {
  if (!skip_spaces(b)) return false;
  if (!token_match(b, "element") && !token_match(b, "comment")) return false;
  if (!skip_spaces(b)) return false;
  struct Name {
    const char* token;
    PlySemantic semantic;
  };
  static constexpr std::array<Name, 6> kNames{{{"vertex", PlySemantic::kVertex},
                                               {"face", PlySemantic::kFace},
                                               {"tristrips", PlySemantic::kTriStrip},
                                               {"edge", PlySemantic::kEdge},
                                               {"material", PlySemantic::kMaterial},
                                               {"TextureFile", PlySemantic::kTextureFile}}};
  for (const Name& n : kNames) {
    if (token_match(b, n.token)) {
      out.semantic = n.semantic;
      out.name = n.token;
      break;
    }
  }
  if (out.semantic == PlySemantic::kInvalid) out.name = b.substr(0, b.find_first_of(" \t\r\n\f", 0));
  if (!skip_spaces(b)) return false;
  if (out.semantic == PlySemantic::kTextureFile) {
    skip_spaces_and_line_end(b);
    return true;
  }
  // Assimp reads the count where the cursor is: for a name it does not know, that is the
  // name, which gives 0 unless the name starts with digits.
  const char* p = b.c_str();
  out.count = strtoul10(p);
  skip_spaces_and_line_end(b);
  for (;;) {
    if (!lines.next(b)) fail(path, "the PLY header ends without end_header");
    skip_comments(b);
    PlyProperty property;
    if (!parse_property(b, property)) break;
    out.properties.push_back(property);
  }
  return true;
}

inline constexpr std::uint64_t kPlyMaxMaterials = 256;
inline constexpr std::uint64_t kPlyMaxKeptValues = std::uint64_t{1} << 20;

struct PlyHeader {
  bool binary = false;
  bool big_endian = false;
  std::vector<PlyElement> elements;
};

// PLYImporter::InternReadFile and PLY::DOM::ParseHeader. Returns false where Assimp
// itself rejects the file.
bool parse_ply_header(PlyLines& lines, std::string& b, PlyHeader& out, const fs::path& path) {
  std::string magic;
  if (!lines.next(magic) || lines.line_length() < 3 || (magic[0] != 'p' && magic[0] != 'P') ||
      (magic[1] != 'l' && magic[1] != 'L') || (magic[2] != 'y' && magic[2] != 'Y')) {
    return false;
  }
  std::string format;
  lines.next(format);
  const char* p = format.c_str();
  Assimp::SkipSpacesAndLineEnd(&p);
  if (!Assimp::TokenMatch(p, "format", 6)) return false;
  if (Assimp::TokenMatch(p, "ascii", 5)) {
    out.binary = false;
  } else if (std::strncmp(p, "binary_", 7) == 0) {
    out.binary = true;
    out.big_endian = p[7] == 'b' || p[7] == 'B';
  } else {
    return false;
  }
  if (!lines.next(b)) fail(path, "the PLY header ends without end_header");
  while (!b.empty()) {
    skip_comments(b);
    PlyElement element;
    if (parse_element(lines, b, element, path)) {
      out.elements.push_back(std::move(element));
    } else if (token_match(b, "end_header")) {
      break;
    } else if (!lines.next(b)) {
      fail(path, "the PLY header ends without end_header");
    }
    if (lines.pos() > PlyLines::kCache) fail(path, "the PLY header is longer than 1 MiB");
  }
  return true;
}

// The least bytes one instance of `e` takes: binary, its scalars and list lengths; ascii,
// a digit and a separator per value. An element without properties counts one byte, as
// Assimp still keeps a record per instance of it.
std::uint64_t least_instance_bytes(const PlyElement& e, bool binary) {
  std::uint64_t bytes = 0;
  for (const PlyProperty& p : e.properties) {
    bytes += binary ? type_size(p.list ? p.count_type : p.type) : 2;
  }
  return std::max<std::uint64_t>(bytes, 1);
}

std::string instance_name(const PlyElement& e, std::uint32_t i) {
  return fmt::format("{} {} of {}", e.name, i, e.count);
}

// PLY::PropertyInstance::ConvertTo<unsigned int> of a list length, refusing the values it
// would convert with undefined behaviour.
bool list_length(double value, std::uint64_t& out) {
  if (!(value >= 0.0 && value < 4294967296.0)) return false;
  out = static_cast<std::uint64_t>(value);
  return true;
}

template <typename T>
T read_binary(const std::string& bytes, std::size_t at, bool big_endian) {
  std::array<unsigned char, sizeof(T)> raw;
  std::memcpy(raw.data(), bytes.data() + at, sizeof(T));
  if (big_endian) std::reverse(raw.begin(), raw.end());
  T value;
  std::memcpy(&value, raw.data(), sizeof(T));
  return value;
}

double binary_value(const std::string& bytes, std::size_t at, PlyType t, bool big_endian) {
  switch (t) {
    case PlyType::kChar: return read_binary<std::int8_t>(bytes, at, big_endian);
    case PlyType::kUChar: return read_binary<std::uint8_t>(bytes, at, big_endian);
    case PlyType::kShort: return read_binary<std::int16_t>(bytes, at, big_endian);
    case PlyType::kUShort: return read_binary<std::uint16_t>(bytes, at, big_endian);
    case PlyType::kInt: return static_cast<std::uint32_t>(read_binary<std::int32_t>(bytes, at, big_endian));
    case PlyType::kUInt: return read_binary<std::uint32_t>(bytes, at, big_endian);
    case PlyType::kFloat: return read_binary<float>(bytes, at, big_endian);
    case PlyType::kDouble: return read_binary<double>(bytes, at, big_endian);
    case PlyType::kInvalid: break;
  }
  return 0.0;
}

// PLY::DOM::ParseElementInstanceListsBinary: every instance must lie inside the file.
void walk_binary(const fs::path& path, const std::string& bytes, std::size_t at, const PlyHeader& h) {
  TriangulationWork polygons(path);
  const auto truncated = [&](const PlyElement& e, std::uint32_t i) {
    fail(path, fmt::format("the data ends inside {} (offset {} of {} bytes): the file is truncated "
                           "or its header promises too much",
                           instance_name(e, i), at, bytes.size()));
  };
  for (const PlyElement& e : h.elements) {
    for (std::uint32_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        std::uint64_t items = 1;
        if (p.list) {
          if (bytes.size() - at < type_size(p.count_type)) truncated(e, i);
          const double length = binary_value(bytes, at, p.count_type, h.big_endian);
          if (!list_length(length, items)) {
            fail(path, fmt::format("{} (offset {}) has a list length of {}", instance_name(e, i), at,
                                   length));
          }
          at += type_size(p.count_type);
        }
        if (items > (bytes.size() - at) / type_size(p.type)) {
          if (p.list) {
            fail(path, fmt::format("{} (offset {}) has a list of {} items, but only {} bytes follow: "
                                   "the file is truncated or corrupt",
                                   instance_name(e, i), at, items, bytes.size() - at));
          }
          truncated(e, i);
        }
        if (p.list && e.semantic == PlySemantic::kFace) polygons.add(items, [&] { return instance_name(e, i); });
        at += items * type_size(p.type);
      }
    }
  }
}

// PLY::PropertyInstance::ParseValue: moves `p` past one value, as Assimp does; returns it
// when it is a list length.
double ascii_value(const char*& p, PlyType t) {
  switch (t) {
    case PlyType::kUInt:
    case PlyType::kUShort:
    case PlyType::kUChar: return strtoul10(p);
    case PlyType::kInt:
    case PlyType::kShort:
    case PlyType::kChar: return static_cast<std::uint32_t>(strtol10(p));
    case PlyType::kFloat: {
      float f = 0.0f;
      p = Assimp::fast_atoreal_move<float, NotANumber>(p, f);
      return f;
    }
    case PlyType::kDouble: {
      double d = 0.0;
      p = Assimp::fast_atoreal_move<double, NotANumber>(p, d);
      return d;
    }
    case PlyType::kInvalid: break;
  }
  return 0.0;
}

// PLY::DOM::ParseElementInstanceLists: one line per instance; a value read from beyond its
// line (Assimp goes on into the buffer's stale tail) or a list longer than its line is an
// error, and so is a file that ends before the last instance.
void walk_ascii(const fs::path& path, PlyLines& lines, std::string& b, const PlyHeader& h) {
  TriangulationWork polygons(path);
  bool have_line = lines.next(b);
  for (const PlyElement& e : h.elements) {
    const bool parsed = e.semantic != PlySemantic::kInvalid && !e.properties.empty();
    for (std::uint32_t i = 0; i < e.count; ++i) {
      if (!have_line) {
        fail(path, fmt::format("the file ends before {} (line {}): it is truncated or its header "
                               "promises too much",
                               instance_name(e, i), lines.line() + 1));
      }
      const char* p = b.c_str();
      const char* const line_end = p + lines.line_length();
      for (std::size_t k = 0; parsed && k < e.properties.size(); ++k) {
        const PlyProperty& property = e.properties[k];
        if (p > line_end) {
          fail(path, fmt::format("line {}: {} has fewer values than its {} properties", lines.line(),
                                 instance_name(e, i), e.properties.size()));
        }
        if (!Assimp::SkipSpaces(&p)) continue;
        const char* value_start = p;
        try {
          if (property.list) {
            std::uint64_t items = 0;
            const double length = ascii_value(p, property.count_type);
            if (!list_length(length, items)) {
              fail(path, fmt::format("line {}: {} has a list length of {}", lines.line(),
                                     instance_name(e, i), length));
            }
            // Each item takes at least a character of the line; an integer item that is
            // not a number leaves Assimp's cursor where it was.
            if (items > lines.line_length()) {
              fail(path, fmt::format("line {}: {} has a list of {} items, more than its line's {} "
                                     "characters",
                                     lines.line(), instance_name(e, i), items, lines.line_length()));
            }
            if (e.semantic == PlySemantic::kFace) {
              polygons.add(items, [&] { return fmt::format("line {}: {}", lines.line(), instance_name(e, i)); });
            }
            for (std::uint64_t item = 0; item < items; ++item) {
              if (!Assimp::SkipSpaces(&p)) {
                fail(path, fmt::format("line {}: {} has a list of {} items, but the line holds "
                                       "only {}",
                                       lines.line(), instance_name(e, i), items, item));
              }
              value_start = p;
              ascii_value(p, property.type);
              if (p == value_start) {
                fail(path, fmt::format("line {}: {} has {} in its list, which is not a number",
                                       lines.line(), instance_name(e, i), word_at(value_start)));
              }
            }
          } else {
            ascii_value(p, property.type);
          }
        } catch (const NotANumber&) {
          fail(path, fmt::format("line {}: {} has {}, which is not a number", lines.line(),
                                 instance_name(e, i), word_at(value_start)));  // so would Assimp
        }
        Assimp::SkipSpacesAndLineEnd(&p);
      }
      have_line = lines.next(b);
    }
  }
}

void check_ply(const fs::path& path, const std::string& bytes) {
  PlyLines lines(path, bytes);
  std::string buffer;
  PlyHeader header;
  if (!parse_ply_header(lines, buffer, header, path)) return;
  // Binary data starts after the end_header line's first line-end byte; Assimp drops one
  // '\n' more, meant for "\r\n".
  std::size_t data = lines.pos();
  if (header.binary && data < bytes.size() && bytes[data] == '\n') ++data;
  // Every instance must fit in what is left: a cheap check first, with the header's words.
  std::uint64_t bytes_left = bytes.size() - std::min(data, bytes.size());
  std::string where = "after the header";
  for (const PlyElement& e : header.elements) {
    const std::string what = e.semantic == PlySemantic::kVertex ? "vertices"
                             : e.semantic == PlySemantic::kFace ? "faces"
                                                                : fmt::format("\"{}\" elements", e.name);
    check_count(path, e.count, what, least_instance_bytes(e, header.binary), header.binary ? 0 : 1,
                bytes_left, where);
    where = fmt::format("left after the {}", what);
  }
  // Assimp keeps every instance of an element that is neither vertex, face nor
  // tristrips, at about 100 bytes a value, and makes each material a whole aiMaterial
  // of some kilobytes; rpu uses neither, so both are capped to keep memory in step with
  // the file's size.
  std::uint64_t kept_values = 0, materials = 0;
  for (const PlyElement& e : header.elements) {
    if (e.semantic == PlySemantic::kEdge || e.semantic == PlySemantic::kMaterial) {
      kept_values += std::uint64_t{e.count} * std::max<std::size_t>(e.properties.size(), 1);
    }
    if (e.semantic == PlySemantic::kMaterial) materials += e.count;
  }
  if (materials > kPlyMaxMaterials) {
    fail(path, fmt::format("the header declares {} materials; Assimp makes a whole material of "
                           "each, and rpu reads at most {} (rpu takes materials from the scene file)",
                           materials, kPlyMaxMaterials));
  }
  // Assimp 5.2 leaks the material list it allocates for a material element of no
  // instances (found by fuzz_mesh_files).
  for (const PlyElement& e : header.elements) {
    if (e.semantic == PlySemantic::kMaterial && e.count == 0) {
      fail(path, fmt::format("the \"{}\" element has no instances; leave it out (Assimp 5.2 mishandles "
                             "an empty material element, and rpu takes materials from the scene file)",
                             e.name));
    }
  }
  if (kept_values > kPlyMaxKeptValues) {
    fail(path, fmt::format("the header declares {} edge and material values; Assimp keeps each at "
                           "about 100 bytes, and rpu reads at most {} (rpu does not use them)",
                           kept_values, kPlyMaxKeptValues));
  }
  if (header.binary) {
    walk_binary(path, bytes, data, header);
  } else {
    walk_ascii(path, lines, buffer, header);
  }
}

}  // namespace

void check_mesh_bytes(const fs::path& path, MeshFormat format, const std::string& bytes) {
  switch (format) {
    case MeshFormat::kPly: check_ply(path, bytes); break;
    case MeshFormat::kOff: check_off(path, bytes); break;
    case MeshFormat::kStl: check_stl(path, bytes); break;
    case MeshFormat::kObj: check_obj(path, bytes); break;
    case MeshFormat::kOther: break;
  }
}

}  // namespace rpu
