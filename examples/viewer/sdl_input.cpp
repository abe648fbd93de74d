// SDL input ↔ viewer input (see sdl_input.h).
#include "sdl_input.h"

#include <array>
#include <utility>

namespace viewer {

namespace {
constexpr std::array<std::pair<Key, SDL_Keycode>, 33> kKeys{{
    {Key::W, SDLK_w},         {Key::A, SDLK_a},         {Key::S, SDLK_s},       {Key::D, SDLK_d},
    {Key::Q, SDLK_q},         {Key::E, SDLK_e},         {Key::Up, SDLK_UP},     {Key::Down, SDLK_DOWN},
    {Key::Left, SDLK_LEFT},   {Key::Right, SDLK_RIGHT}, {Key::Tab, SDLK_TAB},   {Key::Num0, SDLK_0},
    {Key::Num1, SDLK_1},      {Key::Num2, SDLK_2},      {Key::Num3, SDLK_3},    {Key::Num4, SDLK_4},
    {Key::Num5, SDLK_5},      {Key::Num6, SDLK_6},      {Key::Num7, SDLK_7},    {Key::Num8, SDLK_8},
    {Key::Num9, SDLK_9},      {Key::N, SDLK_n},         {Key::M, SDLK_m},       {Key::C, SDLK_c},       {Key::B, SDLK_b},
    {Key::R, SDLK_r},         {Key::F, SDLK_f},         {Key::T, SDLK_t},       {Key::P, SDLK_p},
    {Key::V, SDLK_v},         {Key::H, SDLK_h},         {Key::G, SDLK_g},       {Key::Escape, SDLK_ESCAPE},
}};
// One SDL key per viewer key.
static_assert(kKeys.size() == kKeyCount);
}  // namespace

std::optional<Key> key_from_sdl(SDL_Keycode code) {
  for (const auto& [key, sdl] : kKeys)
    if (sdl == code) return key;
  return std::nullopt;
}

SDL_Keycode key_to_sdl(Key key) {
  for (const auto& [k, sdl] : kKeys)
    if (k == key) return sdl;
  return SDLK_UNKNOWN;
}

SDL_Event to_sdl_event(const Event& event, Uint32 window_id) {
  SDL_Event e{};
  if (const auto* down = std::get_if<KeyDown>(&event)) {
    e.type = SDL_KEYDOWN;
    e.key.state = SDL_PRESSED;
    e.key.keysym.sym = key_to_sdl(down->key);
    e.key.keysym.scancode = SDL_GetScancodeFromKey(e.key.keysym.sym);
    e.key.windowID = window_id;
  } else if (const auto* up = std::get_if<KeyUp>(&event)) {
    e.type = SDL_KEYUP;
    e.key.state = SDL_RELEASED;
    e.key.keysym.sym = key_to_sdl(up->key);
    e.key.keysym.scancode = SDL_GetScancodeFromKey(e.key.keysym.sym);
    e.key.windowID = window_id;
  } else {  // scripts give whole pixels (script.h)
    const auto& motion = std::get<MouseMotion>(event);
    e.type = SDL_MOUSEMOTION;
    e.motion.windowID = window_id;
    e.motion.xrel = static_cast<Sint32>(motion.dx);
    e.motion.yrel = static_cast<Sint32>(motion.dy);
  }
  return e;
}

}  // namespace viewer
