// OBJ + MTL loading: our own validation pass, tinyobjloader for parsing and triangulation,
// then meshes split by material and MTL values mapped onto metal/roughness materials.
//
// tinyobjloader (2.0.0rc10) reads "nan", "1.#IND" or garbage as 0 without a word, reports
// out-of-range indices only as a warning with the file's last line, and cannot tell "Pr 0"
// from "no Pr". So a first pass over the text (validate_obj) checks every number and index
// with its line number before tinyobjloader sees the file, and the MTL reader notes which
// keys each material has and the line of each map statement (tinyobjloader gives materials
// no line numbers). The meshes are then built with every index checked again; the maps
// become texture slots in mtl_textures.cpp.
#include "softpbr/loaders/obj.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <tiny_obj_loader.h>

#include "mtl_textures.h"
#include "softpbr/image/read_file.h"
#include "softpbr/loaders/format_bytes.h"

namespace softpbr::pbr {

namespace fs = std::filesystem;

namespace {

// Files over 1 GiB are refused before reading: tinyobjloader keeps the text, its parse and
// our meshes in memory at once, several times the file size.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 30;
// Vertices of one face: tinyobjloader's ear clipping takes time quadratic in them (a
// 200000-vertex face took a minute); 4096 take milliseconds.
constexpr std::size_t kMaxFaceVertices = 4096;

// ---- Reading files and lines ----------------------------------------------------------------

std::string describe(const fs::path& path) { return path.string(); }

[[noreturn]] void fail(const fs::path& path, std::size_t line, const std::string& what) {
  std::string message = describe(path);
  if (line > 0) message += ":" + std::to_string(line);
  throw LoadError(message + ": " + what);
}

// The whole file, or an error message (empty on success).
std::string read_text(const fs::path& path, std::string& text) {
  const image::FileProblem p = image::read_whole_file(path, kMaxFileBytes, text);
  if (!p) return {};
  if (p.too_large)
    return "file is " + std::to_string(p.size) + " bytes, more than the limit of " + std::to_string(kMaxFileBytes);
  return "cannot open: " + p.reason;
}

// Calls f(line_number, line) for each line, split as tinyobjloader's safeGetline does
// ("\n", "\r\n" or a lone "\r"), so the line numbers agree with its messages.
template <class F>
void for_each_line(std::string_view text, F&& f) {
  std::size_t line = 0, i = 0;
  while (i < text.size()) {
    std::size_t j = i;
    while (j < text.size() && text[j] != '\n' && text[j] != '\r') ++j;
    f(++line, text.substr(i, j - i));
    if (j + 1 < text.size() && text[j] == '\r' && text[j + 1] == '\n') ++j;
    i = j + 1;
  }
}

bool is_space(char c) { return c == ' ' || c == '\t'; }

// Splits on spaces and tabs.
std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !is_space(line[j])) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

std::string quote(std::string_view s) {
  constexpr std::size_t kShown = 40;
  std::string out(1, '\'');  // appended piecewise: GCC 12 warns (-Wrestrict) on "'" + string
  out.append(s.substr(0, kShown));
  out.append(s.size() > kShown ? "…'" : "'");
  return out;
}

// ---- Validation pass ------------------------------------------------------------------------

struct ObjScan {
  std::size_t positions = 0, texcoords = 0, normals = 0;
  std::uint64_t corners = 0;  // face vertices, all faces
  std::vector<std::size_t> position_lines;  // the line of each `v`, for later messages
  std::vector<std::string> warnings;
};

// A finite float, as text: the whole token must be a number (a leading '+' is allowed).
// Returns its value.
double check_number(const fs::path& path, std::size_t line, std::string_view tok, const char* what) {
  std::string_view t = tok;
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
  if (ec == std::errc::result_out_of_range) fail(path, line, std::string(what) + " " + quote(tok) + " is out of range");
  if (ec != std::errc() || end != t.data() + t.size()) fail(path, line, std::string(what) + " " + quote(tok) + " is not a number");
  if (!std::isfinite(x)) fail(path, line, std::string(what) + " " + quote(tok) + " is not a finite number");
  if (std::fabs(x) > std::numeric_limits<float>::max())
    fail(path, line, std::string(what) + " " + quote(tok) + " is beyond the float range");
  return x;
}

// Checks the first `checked` values after the keyword (up to a trailing # comment); there
// must be at least `needed`.
void check_numbers(const fs::path& path, std::size_t line, const std::vector<std::string_view>& tok,
                   std::size_t needed, std::size_t checked, const char* what) {
  std::size_t values = 1;
  while (values < tok.size() && tok[values][0] != '#') ++values;
  if (values - 1 < needed)
    fail(path, line, "'" + std::string(tok[0]) + "' needs " + std::to_string(needed) + " numbers, found " +
                         std::to_string(values - 1));
  for (std::size_t k = 1; k < values && k <= checked; ++k) check_number(path, line, tok[k], what);
}

// An OBJ index as tinyobjloader reads it (an optional sign and digits), or an error.
long long parse_index(const fs::path& path, std::size_t line, std::string_view corner, std::string_view s,
                      const char* what) {
  std::string_view t = s;
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  long long v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (s.empty()) fail(path, line, "face vertex " + quote(corner) + " has an empty " + what + " index");
  if (ec != std::errc() || end != t.data() + t.size())
    fail(path, line, "face vertex " + quote(corner) + ": " + what + " index " + quote(s) + " is not an integer");
  return v;
}

// Resolves a 1-based or negative (relative) OBJ index against `so_far` elements defined
// before this line and `total` in the file; returns the 0-based index or −1 if out of range.
long long resolve(long long index, std::size_t so_far, std::size_t total) {
  if (index > 0) return index <= static_cast<long long>(total) ? index - 1 : -1;
  // Compared without negating: −index overflows for −2^63.
  if (index < 0) return index >= -static_cast<long long>(so_far) ? static_cast<long long>(so_far) + index : -1;
  return -1;
}

std::string range_message(const char* what, long long index, std::size_t so_far, std::size_t total,
                          const char* plural) {
  if (index == 0) return std::string(what) + " index 0 is invalid (OBJ indices start at 1)";
  if (index < 0)
    return std::string(what) + " index " + std::to_string(index) + " is out of range (" + std::to_string(so_far) +
           " " + plural + " defined before this line)";
  return std::string(what) + " index " + std::to_string(index) + " is out of range (" + std::to_string(total) + " " +
         plural + " in the file)";
}

ObjScan validate_obj(const fs::path& path, std::string_view text) {
  if (const void* nul = std::memchr(text.data(), '\0', text.size())) {
    std::size_t line = 1 + static_cast<std::size_t>(std::count(text.data(), static_cast<const char*>(nul), '\n'));
    fail(path, line, "binary data (a NUL byte); not an OBJ text file");
  }
  ObjScan scan;
  std::size_t unknown = 0, unknown_line = 0;
  std::string unknown_keyword;
  // Pass 1: every number, and the counts that positive indices refer to.
  for_each_line(text, [&](std::size_t line, std::string_view s) {
    const std::vector<std::string_view> tok = tokens(s);
    if (tok.empty() || tok[0][0] == '#') return;
    const std::string_view key = tok[0];
    if (key == "v") {
      check_numbers(path, line, tok, 3, 3, "vertex coordinate");
      ++scan.positions;
      scan.position_lines.push_back(line);
    } else if (key == "vt") {
      check_numbers(path, line, tok, 1, 2, "texture coordinate");
      ++scan.texcoords;
    } else if (key == "vn") {
      check_numbers(path, line, tok, 3, 3, "normal coordinate");
      ++scan.normals;
    } else if (key == "vw") {
      // A skin-weight line "vw vertex joint weight joint weight…" (a tinyobjloader extension
      // softpbr does not use): tinyobjloader reads each joint as a real and converts it to
      // int, undefined for inf/NaN or past INT_MAX (fuzz_obj), so each must be a finite
      // number and each joint a whole number in [0, 2^31).
      check_numbers(path, line, tok, 1, 1, "skin weight value");
      for (std::size_t k = 2; k < tok.size() && tok[k][0] != '#'; ++k) {
        const double x = check_number(path, line, tok[k], "skin weight value");
        if (k % 2 == 0 && (!(x >= 0.0 && x < 2147483648.0) || x != std::floor(x)))
          fail(path, line, "skin weight joint " + quote(tok[k]) + " is not a joint index (a whole number in [0, 2^31))");
      }
    } else if (key == "t" && tok.size() >= 3) {
      // A subdivision tag "t name ints/reals/strings values…": tinyobjloader allocates the
      // declared counts (up to 8192 each) per line, so they must be there in the text.
      long long declared = 0;
      for (std::string_view rest = tok[2]; !rest.empty();) {
        const std::size_t slash = std::min(rest.find('/'), rest.size());
        long long n = 0;
        std::from_chars(rest.data(), rest.data() + slash, n);
        declared += std::clamp(n, 0ll, 8192ll);
        rest.remove_prefix(std::min(slash + 1, rest.size()));
      }
      if (declared > static_cast<long long>(tok.size() - 3))
        fail(path, line, "tag " + quote(tok[1]) + " declares " + std::to_string(declared) + " values but has " +
                             std::to_string(tok.size() - 3));
    } else if (key != "f" && key != "l" && key != "p" && key != "g" && key != "o" && key != "s" && key != "t" &&
               key != "usemtl" && key != "mtllib") {
      if (unknown++ == 0) {
        unknown_line = line;
        unknown_keyword = std::string(key);
      }
    }
  });
  // The keyword is quoted only when it looks like one: a file that is not OBJ at all (a scene
  // naming ../../etc/passwd as a mesh) must not have its first line echoed.
  const bool keyword_like = unknown_keyword.size() <= 16 && std::all_of(unknown_keyword.begin(), unknown_keyword.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
  if (unknown > 0)
    scan.warnings.push_back(describe(path) + ":" + std::to_string(unknown_line) + ": " + std::to_string(unknown) +
                            " line(s) with unsupported keywords ignored" +
                            (keyword_like ? " (the first is " + quote(unknown_keyword) + ")" : std::string(" (not an OBJ keyword)")));

  // Pass 2: face indices, relative ones against the counts so far.
  std::size_t v = 0, vt = 0, vn = 0, bad_normals = 0;
  std::string first_bad_normal;
  for_each_line(text, [&](std::size_t line, std::string_view s) {
    const std::vector<std::string_view> tok = tokens(s);
    if (tok.empty()) return;
    if (tok[0] == "v") ++v;
    if (tok[0] == "vt") ++vt;
    if (tok[0] == "vn") ++vn;
    if (tok[0] != "f") return;
    if (tok.size() - 1 > kMaxFaceVertices)
      fail(path, line, "a face of " + std::to_string(tok.size() - 1) + " vertices (the limit is " +
                           std::to_string(kMaxFaceVertices) + ": polygons are triangulated by ear clipping, quadratic in their size)");
    scan.corners += tok.size() - 1;
    for (std::size_t k = 1; k < tok.size(); ++k) {
      const std::string_view corner = tok[k];
      std::string_view parts[3];
      std::size_t n = 0, start = 0;
      for (std::size_t i = 0; i <= corner.size(); ++i) {
        if (i < corner.size() && corner[i] != '/') continue;
        if (n == 3) fail(path, line, "face vertex " + quote(corner) + " has more than three '/'-separated indices");
        parts[n++] = corner.substr(start, i - start);
        start = i + 1;
      }
      const long long pi = parse_index(path, line, corner, parts[0], "position");
      if (resolve(pi, v, scan.positions) < 0) fail(path, line, range_message("position", pi, v, scan.positions, "positions"));
      if (n >= 2 && !(n == 3 && parts[1].empty())) {
        const long long ti = parse_index(path, line, corner, parts[1], "texture");
        if (resolve(ti, vt, scan.texcoords) < 0)
          fail(path, line, range_message("texture", ti, vt, scan.texcoords, "texture coordinates"));
      }
      if (n == 3) {
        const long long ni = parse_index(path, line, corner, parts[2], "normal");
        if (ni == 0) fail(path, line, range_message("normal", ni, vn, scan.normals, "normals"));
        if (resolve(ni, vn, scan.normals) < 0 && bad_normals++ == 0)
          first_bad_normal = describe(path) + ":" + std::to_string(line) + ": " +
                             range_message("normal", ni, vn, scan.normals, "normals");
      }
    }
  });
  if (bad_normals > 0)
    scan.warnings.push_back(first_bad_normal + "; " + std::to_string(bad_normals) +
                            " such normal reference(s) dropped, smooth normals used instead");
  return scan;
}

// The first "line N" in a tinyobjloader message, or 0.
std::size_t line_in(const std::string& message) {
  for (std::size_t at = message.find("line "); at != std::string::npos; at = message.find("line ", at + 1)) {
    std::size_t n = 0, i = at + 5;
    if (i >= message.size() || !std::isdigit(static_cast<unsigned char>(message[i]))) continue;
    while (i < message.size() && std::isdigit(static_cast<unsigned char>(message[i])) && n < 1'000'000'000)
      n = n * 10 + static_cast<std::size_t>(message[i++] - '0');
    return n;
  }
  return 0;
}

// "file:line: message" from a tinyobjloader message: its stray punctuation trimmed and a
// trailing "(line N …)" moved to the front.
std::string located(const fs::path& path, std::string w) {
  const std::size_t b = w.find_first_not_of(" \t\r.");
  if (b == std::string::npos) return {};
  w = w.substr(b, w.find_last_not_of(" \t\r") + 1 - b);
  const std::size_t line = line_in(w);
  std::string where = describe(path);
  if (line > 0) {
    where += ':';
    where += std::to_string(line);  // not ":" + string: GCC 12's -Wrestrict false positive
    const std::size_t paren = w.rfind(" (line ");
    if (paren != std::string::npos && w.back() == ')') w.erase(paren);
  }
  return where + ": " + w;
}

// ---- Materials ------------------------------------------------------------------------------

using detail::MtlInfo;

// What a material's keys are taken to be when the text and tinyobjloader disagree on the
// materials (not expected): Ns present, nothing else, no lines.
MtlInfo fallback_info(const fs::path& file) {
  MtlInfo info{file};
  info.has_ns = true;
  return info;
}

// The MTL keywords of the maps that become texture slots, as tinyobjloader matches them.
constexpr std::pair<std::string_view, detail::MtlMap> kMapKeywords[] = {
    {"map_Kd", detail::kMapKd},   {"map_Ke", detail::kMapKe},   {"map_Pr", detail::kMapPr},
    {"map_Pm", detail::kMapPm},   {"map_Ns", detail::kMapNs},   {"norm", detail::kMapNorm},
    {"map_Bump", detail::kMapBump}, {"map_bump", detail::kMapBump}, {"bump", detail::kMapBump},
    {"map_d", detail::kMapD}};

// The MTL keys whose values are all numbers (Kd/Ka/Ks/Ke take 1 or 3; "Kd spectral …" and
// "Kd xyz …", which tinyobjloader would read as 0, are refused too; Tf is not used).
constexpr std::string_view kMtlNumberKeys[] = {"Ka", "Kd", "Ks", "Ke", "Ns",  "Ni",     "d",     "Tr",
                                               "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor", "illum"};

// Reads mtllib files next to the OBJ file. Warnings and errors are kept here (errors for
// load_obj to throw once tinyobjloader returns, rather than thrown through it).
class MtlReader final : public tinyobj::MaterialReader {
 public:
  MtlReader(fs::path dir, const std::vector<fs::path>& roots) : dir_(std::move(dir)), roots_(roots) {}

  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string* warn, std::string* err) override {
    (void)warn;
    (void)err;
    const fs::path path = dir_ / name;
    std::string text;
    if (std::string problem = detail::outside_roots(path, roots_); !problem.empty()) {
      if (error_.empty()) error_ = describe(path) + ": " + problem;
      return false;
    }
    files.push_back(path.string());
    if (std::string problem = read_text(path, text); !problem.empty()) {
      warnings.push_back(describe(path) + ": " + problem);
      return false;
    }
    if (text.find('\0') != std::string::npos) {
      if (error_.empty()) error_ = describe(path) + ": binary data (a NUL byte); not an MTL text file";
      return false;
    }
    // Which keys each material has, mirroring LoadMtl: a material starts at each `newmtl`
    // (lines are trimmed at both ends first); text before the first one only becomes a
    // material when there is no `newmtl` at all.
    std::vector<MtlInfo> blocks(1, MtlInfo{path});
    std::string bad_number;
    for_each_line(text, [&](std::size_t number, std::string_view line) {
      while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
      while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
      auto starts = [&](std::string_view key) {
        return line.size() > key.size() && line.substr(0, key.size()) == key && is_space(line[key.size()]);
      };
      // tinyobjloader reads "banana", "inf" or "nan" as a number without a word: every value
      // of a numeric key must be a finite number (up to a # comment), as in OBJ files.
      if (bad_number.empty())
        for (const std::string_view key : kMtlNumberKeys)
          if (starts(key)) {
            std::vector<std::string_view> tok = tokens(line);
            if (key == "d" && tok.size() > 1 && tok[1] == "-halo") tok.erase(tok.begin() + 1);
            try {
              check_numbers(path, number, tok, 1, tok.size(), (std::string(key) + " value").c_str());
            } catch (const LoadError& e) {
              bad_number = e.what();
            }
          }
      if (starts("newmtl")) blocks.push_back(MtlInfo{path});
      MtlInfo& b = blocks.back();
      if (starts("Pr")) b.has_pr = true;
      if (starts("Ns")) b.has_ns = true;
      if (starts("Pm")) b.has_pm = true;
      if (starts("Kd")) b.has_kd = true;
      if (starts("Ke")) b.has_ke = true;
      for (const auto& [keyword, map] : kMapKeywords)
        if (starts(keyword)) {
          b.line[map] = number;
          b.keyword[map] = keyword;
        }
    });
    if (!bad_number.empty()) {
      if (error_.empty()) error_ = bad_number;
      return false;
    }
    if (blocks.size() > 1) blocks.erase(blocks.begin());

    const std::size_t before = materials->size();
    std::istringstream in(text);
    std::string mtl_warnings;
    tinyobj::LoadMtl(names, materials, &in, &mtl_warnings, nullptr);
    std::istringstream lines(mtl_warnings);
    for (std::string w; std::getline(lines, w);)
      if (std::string l = located(path, w); !l.empty()) warnings.push_back(l);
    const std::size_t added = materials->size() - before;
    if (added != blocks.size()) blocks.assign(added, fallback_info(path));  // unexpected: trust Ns
    info.insert(info.end(), blocks.begin(), blocks.end());
    return true;
  }

  std::vector<MtlInfo> info;  // parallel to tinyobjloader's materials
  std::vector<std::string> warnings;
  std::vector<std::string> files;  // every MTL file named
  const std::string& error() const { return error_; }

 private:
  fs::path dir_;
  const std::vector<fs::path>& roots_;
  std::string error_;
};

glm::vec3 vec3_of(const tinyobj::real_t* v) { return {v[0], v[1], v[2]}; }

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// MTL → metal/roughness Material:
//   base_color ← Kd, clamped to [0, 1] (an albedo above 1 would create energy)
//   metallic   ← Pm (PBR extension), clamped to [0, 1]; absent → 0
//   roughness  ← Pr (PBR extension), clamped to [0, 1]; absent → roughness_from_phong_exponent(Ns);
//                neither → Material's default
//   emissive   ← Ke, negative components raised to 0
//   texture maps (when `textures` is given) ← detail::map_textures (obj.h lists the mapping)
// Ka, Ks, d/Tr, Ni, illum and the other extension keys are not used.
Material mtl_to_material(const tinyobj::material_t& m, const MtlInfo& info, std::vector<std::string>& warnings,
                         detail::MtlTextures* textures) {
  const std::string where = describe(info.file) + ": material '" + m.name + "'";
  const glm::vec3 kd = vec3_of(m.diffuse), ke = vec3_of(m.emission);
  if (!finite3(kd) || !finite3(ke) || !std::isfinite(m.roughness) || !std::isfinite(m.metallic) ||
      !std::isfinite(m.shininess))
    throw LoadError(where + ": Kd, Ke, Pr, Pm and Ns must be finite numbers");
  Material out;
  out.base_color = glm::clamp(kd, 0.0f, 1.0f);
  if (out.base_color != kd) warnings.push_back(where + ": Kd clamped to [0, 1]");
  out.metallic = std::clamp(m.metallic, 0.0f, 1.0f);
  if (out.metallic != m.metallic) warnings.push_back(where + ": Pm clamped to [0, 1]");
  if (info.has_pr) {
    out.roughness = std::clamp(m.roughness, 0.0f, 1.0f);
    if (out.roughness != m.roughness) warnings.push_back(where + ": Pr clamped to [0, 1]");
  } else if (info.has_ns) {
    out.roughness = roughness_from_phong_exponent(m.shininess);
  }
  out.emissive = glm::max(ke, glm::vec3(0.0f));
  if (out.emissive != ke) warnings.push_back(where + ": negative Ke raised to 0");
  if (textures) detail::map_textures(m, info, out, *textures);
  return out;
}

// ---- Meshes ---------------------------------------------------------------------------------

struct CornerKey {
  int v, vt, vn;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    std::uint64_t h = static_cast<std::uint32_t>(k.v);
    h = h * 0x9e3779b97f4a7c15ull ^ static_cast<std::uint32_t>(k.vt);
    h = h * 0x9e3779b97f4a7c15ull ^ static_cast<std::uint32_t>(k.vn);
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

// tinyobjloader's warnings, one per line, located, repeats counted. Its "indices out of
// bounds" notes are left out: validate_obj has reported those with their own lines.
void add_warnings(const fs::path& path, const std::string& text, std::vector<std::string>& out) {
  std::vector<std::pair<std::string, int>> unique;
  std::istringstream in(text);
  for (std::string w; std::getline(in, w);) {
    if (w.find("indices out of bounds") != std::string::npos) continue;
    w = located(path, w);
    if (w.empty()) continue;
    auto it = std::find_if(unique.begin(), unique.end(), [&](const auto& u) { return u.first == w; });
    if (it == unique.end()) unique.emplace_back(w, 1);
    else ++it->second;
  }
  for (const auto& [w, n] : unique) out.push_back(n > 1 ? w + " (" + std::to_string(n) + " times)" : w);
}

class MeshBuilder {
 public:
  MeshBuilder(const fs::path& path, const tinyobj::attrib_t& attrib, const ObjScan& scan)
      : path_(path), attrib_(attrib), scan_(scan), positions_(attrib.vertices.size() / 3),
        texcoords_(attrib.texcoords.size() / 2), normals_(attrib.normals.size() / 3) {}

  // Appends one ObjShape per material used by `shape`, in order of first use.
  void add(const tinyobj::shape_t& shape, int material_count, std::vector<ObjShape>& out) {
    const tinyobj::mesh_t& m = shape.mesh;
    const std::size_t faces = m.num_face_vertices.size();
    if (m.indices.size() != faces * 3 || m.material_ids.size() != faces ||
        std::any_of(m.num_face_vertices.begin(), m.num_face_vertices.end(), [](unsigned char n) { return n != 3; }))
      fail(path_, 0, "shape '" + shape.name + "': inconsistent face data from the parser");
    for (const tinyobj::index_t& idx : m.indices) (void)checked(idx);  // before any attribute is read

    std::vector<int> materials;  // in order of first use
    std::vector<std::vector<std::size_t>> faces_of;
    for (std::size_t f = 0; f < faces; ++f) {
      const int id = m.material_ids[f];
      if (id < -1 || id >= material_count)
        fail(path_, 0, "shape '" + shape.name + "': material index " + std::to_string(id) + " is out of range");
      const auto it = std::find(materials.begin(), materials.end(), id);
      if (it == materials.end()) {
        materials.push_back(id);
        faces_of.emplace_back();
        faces_of.back().push_back(f);
      } else {
        faces_of[static_cast<std::size_t>(it - materials.begin())].push_back(f);
      }
    }

    Mesh smooth;  // per position index, computed when a vertex needs it
    std::unordered_map<int, std::uint32_t> smooth_index;
    for (std::size_t g = 0; g < materials.size(); ++g) {
      ObjShape piece{shape.name, {}, materials[g]};
      std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> shared;
      std::vector<std::uint32_t> needs_normal;
      for (const std::size_t f : faces_of[g])
        for (int k = 0; k < 3; ++k) {
          const tinyobj::index_t& idx = m.indices[f * 3 + static_cast<std::size_t>(k)];
          const CornerKey key = checked(idx);
          const auto [it, inserted] = shared.try_emplace(key, static_cast<std::uint32_t>(piece.mesh.vertices.size()));
          if (inserted) {
            if (piece.mesh.vertices.size() >= std::numeric_limits<std::uint32_t>::max())
              fail(path_, 0, "shape '" + shape.name + "' has more than 2^32 - 1 vertices");
            const auto* p = &attrib_.vertices[static_cast<std::size_t>(key.v) * 3];
            MeshVertex vert{{p[0], p[1], p[2]}, glm::vec3(0.0f), glm::vec2(0.0f)};
            if (!finite3(vert.position)) fail(path_, line_of_position(key.v), "vertex position is not finite");
            if (key.vt >= 0) {
              const auto* t = &attrib_.texcoords[static_cast<std::size_t>(key.vt) * 2];
              vert.uv = {t[0], 1.0f - t[1]};  // OBJ's v grows up the image, softpbr's down (obj.h)
              if (!std::isfinite(vert.uv.x) || !std::isfinite(vert.uv.y))
                fail(path_, 0, "texture coordinate " + std::to_string(key.vt + 1) + " is not finite");
            }
            const glm::dvec3 n = key.vn >= 0 ? glm::dvec3(vec3_of(&attrib_.normals[static_cast<std::size_t>(key.vn) * 3]))
                                             : glm::dvec3(0.0);
            const double n2 = glm::dot(n, n);
            if (n2 > 0.0 && std::isfinite(n2)) vert.normal = glm::vec3(n / std::sqrt(n2));
            else needs_normal.push_back(it->second);
            piece.mesh.vertices.push_back(vert);
            position_of_.push_back(key.v);
          }
          piece.mesh.indices.push_back(it->second);
        }
      if (!needs_normal.empty()) {
        if (smooth.vertices.empty()) smooth_normals(m, smooth, smooth_index);
        for (const std::uint32_t i : needs_normal)
          piece.mesh.vertices[i].normal = smooth.vertices[smooth_index.at(position_of_[i])].normal;
      }
      position_of_.clear();
      out.push_back(std::move(piece));
    }
  }

 private:
  std::size_t line_of_position(int v) const {
    return static_cast<std::size_t>(v) < scan_.position_lines.size() ? scan_.position_lines[static_cast<std::size_t>(v)] : 0;
  }

  // The corner's indices, checked; a normal index out of range becomes −1 (warned earlier).
  CornerKey checked(const tinyobj::index_t& idx) const {
    if (idx.vertex_index < 0 || static_cast<std::size_t>(idx.vertex_index) >= positions_)
      fail(path_, 0, "a face refers to position " + std::to_string(idx.vertex_index + 1) + " of " +
                         std::to_string(positions_));
    if (idx.texcoord_index < -1 ||
        (idx.texcoord_index >= 0 && static_cast<std::size_t>(idx.texcoord_index) >= texcoords_))
      fail(path_, 0, "a face refers to texture coordinate " + std::to_string(idx.texcoord_index + 1) + " of " +
                         std::to_string(texcoords_));
    const bool normal_ok = idx.normal_index >= 0 && static_cast<std::size_t>(idx.normal_index) < normals_;
    return {idx.vertex_index, idx.texcoord_index, normal_ok ? idx.normal_index : -1};
  }

  // Smooth normals of the whole shape (all its materials), one per position index.
  void smooth_normals(const tinyobj::mesh_t& m, Mesh& smooth, std::unordered_map<int, std::uint32_t>& index) const {
    for (const tinyobj::index_t& idx : m.indices) {
      const auto [it, inserted] = index.try_emplace(idx.vertex_index, static_cast<std::uint32_t>(smooth.vertices.size()));
      if (inserted) {
        const auto* p = &attrib_.vertices[static_cast<std::size_t>(idx.vertex_index) * 3];  // add() checked it
        smooth.vertices.push_back({{p[0], p[1], p[2]}, glm::vec3(0.0f), glm::vec2(0.0f)});
      }
      smooth.indices.push_back(it->second);
    }
    compute_smooth_normals(smooth);
  }

  const fs::path& path_;
  const tinyobj::attrib_t& attrib_;
  const ObjScan& scan_;
  std::size_t positions_, texcoords_, normals_;
  std::vector<int> position_of_;  // per vertex of the piece being built
};

}  // namespace

float roughness_from_phong_exponent(float ns) {
  if (!(ns > 0.0f)) return 1.0f;  // also NaN
  const double alpha = std::sqrt(2.0 / (static_cast<double>(ns) + 2.0));
  return std::clamp(static_cast<float>(std::sqrt(alpha)), 0.0f, 1.0f);
}

ObjModel load_obj(const fs::path& path, const ObjOptions& options) {
  detail::TextureCache cache;
  cache.set_roots(options.roots);
  return detail::load_obj(path, options, cache);
}

ObjModel detail::load_obj(const fs::path& path, const ObjOptions& options, TextureCache& cache) {
  std::string text;
  if (std::string problem = detail::outside_roots(path, options.roots); !problem.empty()) fail(path, 0, problem);
  if (std::string problem = read_text(path, text); !problem.empty()) fail(path, 0, problem);
  ObjScan scan = validate_obj(path, text);
  // Measured peak of a 142 MB file (3 million vertices and triangles): 1.15 GB, about 8
  // times the text; per element, what tinyobjloader and MeshBuilder keep.
  const std::uint64_t estimate = text.size() + 12 * std::uint64_t{scan.positions} + 8 * std::uint64_t{scan.texcoords} +
                                 12 * std::uint64_t{scan.normals} + 100 * scan.corners;
  if (estimate > options.memory_limit)
    fail(path, 0, "parsing it needs an estimated " + format_bytes(estimate) + ", over the memory limit of " +
                      format_bytes(options.memory_limit));

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  MtlReader mtl(path.parent_path(), options.roots);
  std::istringstream in(std::move(text));
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, &mtl,
                                   /*triangulate=*/true, /*default_vcols_fallback=*/false);
  if (!mtl.error().empty()) throw LoadError(mtl.error());
  if (!ok || !err.empty()) {
    const std::string first = located(path, err.substr(0, err.find('\n')));
    throw LoadError(first.empty() ? describe(path) + ": parse error" : first);
  }
  if (attrib.vertices.size() != scan.positions * 3 || attrib.texcoords.size() != scan.texcoords * 2 ||
      attrib.normals.size() != scan.normals * 3)
    fail(path, 0, "the parser and the validation pass disagree on the number of vertices");

  ObjModel model;
  model.files.push_back(path.string());
  model.files.insert(model.files.end(), mtl.files.begin(), mtl.files.end());
  model.warnings = std::move(scan.warnings);
  model.warnings.insert(model.warnings.end(), mtl.warnings.begin(), mtl.warnings.end());
  add_warnings(path, warn, model.warnings);
  if (mtl.info.size() != materials.size()) mtl.info.resize(materials.size(), fallback_info(path));
  detail::MtlTextures textures{cache, options.texture_memory_limit, cache.bytes(), model.warnings, options.missing_images};
  for (std::size_t i = 0; i < materials.size(); ++i) {
    std::string name = materials[i].name;
    name.erase(0, name.find_first_not_of(" \t"));
    model.materials.emplace_back(
        name, mtl_to_material(materials[i], mtl.info[i], model.warnings, options.textures ? &textures : nullptr));
  }
  model.texture_bytes = cache.bytes() - textures.start;

  MeshBuilder builder(path, attrib, scan);
  std::size_t lines = 0, points = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    builder.add(shape, static_cast<int>(materials.size()), model.shapes);
    lines += shape.lines.num_line_vertices.size();
    points += shape.points.indices.size();
  }
  if (lines > 0 || points > 0)
    model.warnings.push_back(describe(path) + ": " + std::to_string(lines) + " line(s) and " + std::to_string(points) +
                             " point(s) ignored (only faces are drawn)");
  return model;
}

Mesh merge_shapes(const ObjModel& model) {
  // A stream is kept when every shape with vertices has it: the merged stream must have one
  // entry per vertex, and values for the shapes without it would be invented.
  bool tangents = true, uv1 = true, colors = true;
  for (const ObjShape& shape : model.shapes) {
    validate_streams(shape.mesh);
    if (shape.mesh.vertices.empty()) continue;
    tangents = tangents && !shape.mesh.tangents.empty();
    uv1 = uv1 && !shape.mesh.uv1.empty();
    colors = colors && !shape.mesh.colors.empty();
  }
  Mesh out;
  for (const ObjShape& shape : model.shapes) {
    const Mesh& m = shape.mesh;
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.insert(out.vertices.end(), m.vertices.begin(), m.vertices.end());
    for (const std::uint32_t i : m.indices) out.indices.push_back(base + i);
    if (tangents) out.tangents.insert(out.tangents.end(), m.tangents.begin(), m.tangents.end());
    if (uv1) out.uv1.insert(out.uv1.end(), m.uv1.begin(), m.uv1.end());
    if (colors) out.colors.insert(out.colors.end(), m.colors.begin(), m.colors.end());
  }
  return out;
}

}  // namespace softpbr::pbr
