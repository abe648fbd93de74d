// The SDL key table and SDL events made from viewer events.
#include <doctest/doctest.h>

#include <set>

#include "sdl_input.h"

using namespace viewer;

TEST_CASE("every viewer key has its own SDL key code that maps back to it") {
  std::set<SDL_Keycode> seen;
  for (std::size_t k = 0; k < kKeyCount; ++k) {
    const Key key = static_cast<Key>(k);
    CAPTURE(key_name(key));
    const SDL_Keycode code = key_to_sdl(key);
    CHECK(code != SDLK_UNKNOWN);
    CHECK(seen.insert(code).second);
    const auto back = key_from_sdl(code);
    REQUIRE(back.has_value());
    CHECK(*back == key);
  }
  // Letters name their key, digits their preset.
  CHECK(key_to_sdl(Key::W) == SDLK_w);
  CHECK(key_to_sdl(Key::Num7) == SDLK_7);
  CHECK(key_to_sdl(Key::Escape) == SDLK_ESCAPE);
  CHECK_FALSE(key_from_sdl(SDLK_z).has_value());
}

TEST_CASE("viewer events become SDL key and relative mouse events") {
  const SDL_Event down = to_sdl_event(KeyDown{Key::M}, 7);
  CHECK(down.type == SDL_KEYDOWN);
  CHECK(down.key.keysym.sym == SDLK_m);
  CHECK(down.key.repeat == 0);
  CHECK(down.key.windowID == 7u);
  const SDL_Event up = to_sdl_event(KeyUp{Key::Tab}, 7);
  CHECK(up.type == SDL_KEYUP);
  CHECK(up.key.keysym.sym == SDLK_TAB);
  const SDL_Event motion = to_sdl_event(MouseMotion{60.0f, -30.0f}, 7);
  CHECK(motion.type == SDL_MOUSEMOTION);
  CHECK(motion.motion.xrel == 60);
  CHECK(motion.motion.yrel == -30);
}
