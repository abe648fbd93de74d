// viewer/sdl_input.h — between SDL's input events and the viewer's (input.h): the key
// table, and SDL events made from viewer events so a script replays through the same
// event handling as a person at the keyboard.
#pragma once

#include <optional>

#include <SDL.h>

#include "input.h"

namespace viewer {

// The viewer key for an SDL key code (layout-dependent: the key labelled W is W).
std::optional<Key> key_from_sdl(SDL_Keycode code);
SDL_Keycode key_to_sdl(Key key);

// An SDL event equivalent to `event` (key down/up without repeat, relative mouse motion
// with whole-pixel xrel/yrel) for the window `window_id`.
SDL_Event to_sdl_event(const Event& event, Uint32 window_id);

}  // namespace viewer
