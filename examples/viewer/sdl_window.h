// viewer/sdl_window.h — the thin SDL2 part of the viewer: a window that shows an RGBA8
// image scaled to fill it (nearest pixel) and reads back what it shows.
#pragma once

#include <string>

#include <SDL.h>

#include "softpbr/raster/target.h"

namespace viewer {

class SdlWindow {
 public:
  // Opens a window of width × height pixels. `software` forces SDL's software renderer
  // (script mode: exact pixels, no GPU); otherwise SDL picks, falling back to software.
  // Throws std::runtime_error with SDL's message when SDL cannot open it.
  SdlWindow(const std::string& title, int width, int height, bool resizable, bool software);
  ~SdlWindow();
  SdlWindow(const SdlWindow&) = delete;
  SdlWindow& operator=(const SdlWindow&) = delete;

  // The size of the drawable area in pixels.
  int width() const;
  int height() const;

  // Draws `image` over the whole window (not yet presented).
  void draw(const softpbr::raster::Image8& image);
  // The window's pixels as drawn since the last present(), RGBA8 with alpha 255.
  softpbr::raster::Image8 read_back();
  void present();
  void set_title(const std::string& title);
  Uint32 id() const { return SDL_GetWindowID(window_); }

 private:
  SDL_Window* window_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  SDL_Texture* texture_ = nullptr;
  int texture_width_ = 0;
  int texture_height_ = 0;
};

}  // namespace viewer
