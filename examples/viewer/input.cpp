// Key names for scripts (see input.h).
#include "input.h"

#include <array>
#include <utility>

namespace viewer {

namespace {
constexpr std::array<std::pair<Key, std::string_view>, 33> kNames{{
    {Key::W, "w"},        {Key::A, "a"},         {Key::S, "s"},       {Key::D, "d"},
    {Key::Q, "q"},        {Key::E, "e"},         {Key::Up, "up"},     {Key::Down, "down"},
    {Key::Left, "left"},  {Key::Right, "right"}, {Key::Tab, "tab"},   {Key::Num0, "0"},
    {Key::Num1, "1"},     {Key::Num2, "2"},      {Key::Num3, "3"},    {Key::Num4, "4"},
    {Key::Num5, "5"},     {Key::Num6, "6"},      {Key::Num7, "7"},    {Key::Num8, "8"},
    {Key::Num9, "9"},     {Key::N, "n"},         {Key::M, "m"},       {Key::C, "c"},       {Key::B, "b"},
    {Key::R, "r"},        {Key::F, "f"},         {Key::T, "t"},       {Key::P, "p"},
    {Key::V, "v"},        {Key::H, "h"},         {Key::G, "g"},       {Key::Escape, "escape"},
}};
// One name per key.
static_assert(kNames.size() == kKeyCount);
}  // namespace

std::optional<Key> key_from_name(std::string_view name) {
  for (const auto& [key, n] : kNames)
    if (n == name) return key;
  return std::nullopt;
}

std::string_view key_name(Key key) {
  for (const auto& [k, n] : kNames)
    if (k == key) return n;
  return "?";
}

}  // namespace viewer
