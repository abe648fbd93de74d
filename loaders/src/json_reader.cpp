// Checked reading of untrusted JSON (see json_reader.h).
#include "json_reader.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <unordered_set>

namespace softpbr::pbr::json_reader {

std::string escape_token(std::string_view key) {
  std::string out;
  for (const char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

Node Node::child(std::string_view key) const { return {value.at(std::string(key)), pointer + "/" + escape_token(key)}; }
Node Node::at(std::size_t index) const { return {value.at(index), pointer + "/" + std::to_string(index)}; }

std::string show(const Json& value) {
  // Control characters and long strings would break the one-line message.
  // Large arrays and objects are summarised rather than printed whole.
  if ((value.is_array() || value.is_object()) && value.size() > 16)
    return std::string(value.is_array() ? "an array of " : "an object of ") + std::to_string(value.size()) +
           (value.is_array() ? " values" : " keys");
  std::string s = value.dump(-1, ' ', true, Json::error_handler_t::replace);
  constexpr std::size_t kShown = 40;
  if (s.size() > kShown) s = s.substr(0, kShown) + "...";
  return s;
}

std::string show_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

std::string show_rounded(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

namespace {
const char* type_name(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::string: return "a string";
    case Json::value_t::array: return "an array";
    case Json::value_t::object: return "an object";
    default: return "a number";
  }
}

// Levenshtein distance, for "did you mean".
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string list(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string range_text(double lo, double hi, bool open_lo, bool open_hi) {
  constexpr double kBig = 1e29;  // bounds this large mean "unbounded" in messages
  if (lo <= -kBig && hi >= kBig) return "";
  if (hi >= kBig) return std::string(open_lo ? " > " : " >= ") + show_number(lo);
  if (lo <= -kBig) return std::string(open_hi ? " < " : " <= ") + show_number(hi);
  return std::string(" in ") + (open_lo ? "(" : "[") + show_number(lo) + ", " + show_number(hi) + (open_hi ? ")" : "]");
}
}  // namespace

namespace {
// A SAX pass that tracks the pointer of the current value and the keys of each open object.
class DuplicateFinder : public nlohmann::json_sax<Json> {
 public:
  explicit DuplicateFinder(const StructureLimits& limits) : limits_(limits) {}
  std::optional<Problem> found;
  Counts counts() const { return {values_, containers_, keys_}; }

  bool null() override { return value(); }
  // Every value and container counts against kMaxValues / kMaxContainers: they bound the
  // DOM built next (nlohmann's values take 16 bytes, a container's node more).
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    value();
    return push(true);
  }
  bool key(string_t& k) override {
    ++keys_;
    Frame& top = stack_.back();
    top.key = k;
    if (!top.keys.insert(k).second) {  // a hash set: linear in the number of keys
      found = Problem{pointer(), "duplicate key " + show(Json(k)) + " (each key may appear once per object)"};
      return false;  // stop parsing
    }
    return true;
  }
  bool end_object() override { return pop(); }
  bool start_array(std::size_t) override {
    value();
    return push(false);
  }
  bool end_array() override { return pop(); }
  // Syntax errors are left to the DOM parse that follows (its message has the line and
  // column); a number beyond double's range (406: "1e400") has neither there, so it is
  // reported here with its pointer.
  bool parse_error(std::size_t, const std::string& token, const nlohmann::detail::exception& e) override {
    if (e.id == 406) {
      value();
      found = Problem{pointer(), "the number " + (token.size() > 40 ? token.substr(0, 40) + "..." : token) +
                                     " is out of range (beyond +-1.8e308)"};
    }
    return false;
  }

 private:
  struct Frame {
    bool object;
    std::unordered_set<std::string> keys;
    std::string key;
    long index;
  };
  bool value() {
    if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
    if (++values_ > limits_.max_values) {
      found = Problem{pointer(), "more than " + std::to_string(limits_.max_values) +
                                     " values in the file (the limit that bounds its memory)"};
      return false;
    }
    return true;
  }
  bool push(bool object) {
    if (++containers_ > limits_.max_containers) {
      found = Problem{pointer(), "more than " + std::to_string(limits_.max_containers) +
                                     " objects and arrays in the file (the limit that bounds its memory)"};
      return false;
    }
    if (stack_.size() >= limits_.max_depth) {
      found = Problem{pointer(), "nested deeper than " + std::to_string(limits_.max_depth) + " levels"};
      return false;
    }
    stack_.push_back({object, {}, {}, -1});
    return true;
  }
  bool pop() {
    stack_.pop_back();
    return true;
  }
  std::string pointer() const {
    std::string p;
    for (const Frame& f : stack_) {
      p.push_back('/');
      p.append(f.object ? escape_token(f.key) : std::to_string(f.index));
    }
    return p;
  }
  StructureLimits limits_;
  std::vector<Frame> stack_;
  std::size_t values_ = 0, containers_ = 0, keys_ = 0;
};
}  // namespace

std::optional<Problem> find_structure_problem(std::string_view text, Counts* counts, const StructureLimits& limits) {
  DuplicateFinder finder(limits);
  Json::sax_parse(text.begin(), text.end(), &finder, nlohmann::detail::input_format_t::json, true, true);
  if (counts) *counts = finder.counts();
  return finder.found;
}

std::string shown_pointer(std::string_view pointer) {
  // Each reference token at most kShown bytes: a 10 MB key is not a 10 MB line.
  constexpr std::size_t kShown = 40;
  std::string out;
  for (std::size_t at = 0; at < pointer.size();) {
    const std::size_t end = std::min(pointer.find('/', at + 1), pointer.size());
    const std::string_view token = pointer.substr(at, end - at);  // "/key"
    out.append(token.substr(0, kShown + 1));
    if (token.size() > kShown + 1) out.append("...");
    at = end;
  }
  return out;
}

void Reader::fail(const std::string& pointer, const std::string& what) const {
  constexpr std::size_t kMaxWhat = 600;  // the longest "expected one of" list is half that
  std::string line = file_ + ": " + (pointer.empty() ? std::string("(top level)") : shown_pointer(pointer)) + ": " +
                     (what.size() > kMaxWhat ? what.substr(0, kMaxWhat) + "..." : what);
  // Keys are the file's text: keep the message one line whatever they hold.
  for (char& c : line)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  throw Error(line, pointer);
}
void Reader::fail(const Node& node, const std::string& what) const { fail(node.pointer, what); }

void Reader::object(const Node& node, std::initializer_list<std::string_view> allowed) const {
  if (!node.value.is_object()) fail(node, std::string("expected an object, got ") + show(node.value));
  for (const auto& [key, value] : node.value.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string what = "unknown key \"" + key.substr(0, 40) + (key.size() > 40 ? "...\"" : "\"");
    std::string_view best;
    std::size_t best_distance = 3;  // suggest only close misspellings
    for (const std::string_view a : allowed) {
      if (key.size() > a.size() + best_distance) continue;  // too far; and keeps a huge key linear
      const std::size_t d = edit_distance(key, a);
      if (d < best_distance) best_distance = d, best = a;
    }
    if (!best.empty()) what += " (did you mean \"" + std::string(best) + "\"?)";
    else {
      std::vector<std::string> names(allowed.begin(), allowed.end());
      what += " (expected one of: " + list(names) + ")";
    }
    fail(node.pointer + "/" + escape_token(key), what);
  }
}

std::optional<Node> Reader::member(const Node& node, std::string_view key) const {
  const auto it = node.value.find(key);
  if (it == node.value.end()) return std::nullopt;
  return Node{*it, node.pointer + "/" + escape_token(key)};
}

Node Reader::required(const Node& node, std::string_view key) const {
  if (auto m = member(node, key)) return *m;
  fail(node, "missing key \"" + std::string(key) + "\"");
}

double Reader::number(const Node& node, double lo, double hi, bool open_lo, bool open_hi) const {
  const std::string range = range_text(lo, hi, open_lo, open_hi);
  const std::string expected = "expected a number" + range;
  if (!node.value.is_number()) fail(node, expected + ", got " + show(node.value));
  const double x = node.value.get<double>();
  const bool ok = std::isfinite(x) && (open_lo ? x > lo : x >= lo) && (open_hi ? x < hi : x <= hi);
  constexpr double kHuge = 1e30;  // bounds of this size are "unbounded" in messages: say it
  if (!ok && std::fabs(x) > kHuge && (lo <= -kHuge || hi >= kHuge))
    fail(node, expected + (range.empty() ? "" : " and") + " at most 1e+30 in magnitude, got " + show(node.value));
  if (!ok) fail(node, expected + ", got " + show(node.value));
  return x;
}

float Reader::number_f(const Node& node, double lo, double hi, bool open_lo, bool open_hi) const {
  const double x = number(node, lo, hi, open_lo, open_hi);
  const float f = static_cast<float>(x);
  if (!std::isfinite(f)) fail(node, "expected a number within float range (|x| < 3.4e38), got " + show(node.value));
  // A non-zero value that rounds to 0 in float (or leaves the open range) is out of range too.
  if ((open_lo && !(f > static_cast<float>(lo))) || (open_hi && !(f < static_cast<float>(hi))))
    fail(node, "expected a number" + range_text(lo, hi, open_lo, open_hi) + " in float precision, got " +
                   show(node.value));
  return f;
}

long long Reader::integer(const Node& node, long long lo, long long hi) const {
  const std::string expected = "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (node.value.is_number_integer()) {
    const bool is_unsigned = node.value.is_number_unsigned();
    if (is_unsigned && node.value.get<unsigned long long>() > static_cast<unsigned long long>(hi))
      fail(node, expected + ", got " + show(node.value));
    const long long x = is_unsigned ? static_cast<long long>(node.value.get<unsigned long long>())
                                    : node.value.get<long long>();
    if (x < lo || x > hi) fail(node, expected + ", got " + show(node.value));
    return x;
  }
  if (node.value.is_number_float()) {
    // 64.0 is accepted as 64; 64.5 is not.
    const double x = node.value.get<double>();
    if (std::isfinite(x) && x == std::floor(x) && x >= static_cast<double>(lo) && x <= static_cast<double>(hi))
      return static_cast<long long>(x);
  }
  fail(node, expected + ", got " + show(node.value));
}

std::string Reader::string(const Node& node) const {
  if (!node.value.is_string()) fail(node, std::string("expected a string, got ") + show(node.value));
  const std::string& s = node.value.get_ref<const std::string&>();
  if (s.find('\0') != std::string::npos) fail(node, "expected a string without NUL characters (\\u0000), got " + show(node.value));
  return s;
}

bool Reader::boolean(const Node& node) const {
  if (!node.value.is_boolean()) fail(node, std::string("expected true or false, got ") + show(node.value));
  return node.value.get<bool>();
}

std::string Reader::choice(const Node& node, const std::vector<std::string>& names) const {
  if (!node.value.is_string() || std::find(names.begin(), names.end(), node.value.get<std::string>()) == names.end())
    fail(node, "expected one of " + list(names) + ", got " + show(node.value));
  return node.value.get<std::string>();
}

std::vector<float> Reader::numbers(const Node& node, std::size_t n, double lo, double hi) const {
  if (!node.value.is_array() || node.value.size() != n)
    fail(node, "expected an array of " + std::to_string(n) + " numbers" + range_text(lo, hi, false, false) +
                   ", got " + show(node.value));
  std::vector<float> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(number_f(node.at(i), lo, hi));
  return out;
}

glm::vec3 Reader::vec3(const Node& node, double lo, double hi) const {
  const std::vector<float> v = numbers(node, 3, lo, hi);
  return {v[0], v[1], v[2]};
}

std::size_t Reader::array(const Node& node, std::size_t max_count, const std::string& limit_reason) const {
  if (!node.value.is_array()) fail(node, std::string("expected an array, got ") + type_name(node.value));
  if (node.value.size() > max_count)
    fail(node, "too many entries: " + std::to_string(node.value.size()) + " (the limit is " +
                   std::to_string(max_count) + ": " + limit_reason + ")");
  return node.value.size();
}

}  // namespace softpbr::pbr::json_reader
