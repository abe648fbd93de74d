// The SDL2 window of the viewer (see sdl_window.h).
#include "sdl_window.h"

#include <stdexcept>

namespace viewer {

namespace {
[[noreturn]] void sdl_fail(const std::string& what) {
  throw std::runtime_error(what + ": " + SDL_GetError());
}
}  // namespace

SdlWindow::SdlWindow(const std::string& title, int width, int height, bool resizable, bool software) {
  if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) sdl_fail("cannot start SDL video");
  // Scale low-resolution frames up by repeating pixels, not by filtering.
  SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "0");
  window_ = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, width, height,
                             resizable ? SDL_WINDOW_RESIZABLE : 0);
  if (!window_) {
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
    sdl_fail("cannot open a window");
  }
  if (!software) renderer_ = SDL_CreateRenderer(window_, -1, 0);
  if (!renderer_) renderer_ = SDL_CreateRenderer(window_, -1, SDL_RENDERER_SOFTWARE);
  if (!renderer_) {
    SDL_DestroyWindow(window_);
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
    sdl_fail("cannot create an SDL renderer");
  }
}

SdlWindow::~SdlWindow() {
  if (texture_) SDL_DestroyTexture(texture_);
  SDL_DestroyRenderer(renderer_);
  SDL_DestroyWindow(window_);
  SDL_QuitSubSystem(SDL_INIT_VIDEO);
}

int SdlWindow::width() const {
  int w = 0, h = 0;
  SDL_GetRendererOutputSize(renderer_, &w, &h);
  return w;
}

int SdlWindow::height() const {
  int w = 0, h = 0;
  SDL_GetRendererOutputSize(renderer_, &w, &h);
  return h;
}

void SdlWindow::draw(const softpbr::raster::Image8& image) {
  if (!texture_ || texture_width_ != image.width || texture_height_ != image.height) {
    if (texture_) SDL_DestroyTexture(texture_);
    // RGBA32 is R, G, B, A in byte order on every endianness: Image8's layout.
    texture_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, image.width,
                                 image.height);
    if (!texture_) sdl_fail("cannot create a texture");
    SDL_SetTextureBlendMode(texture_, SDL_BLENDMODE_NONE);
    texture_width_ = image.width;
    texture_height_ = image.height;
  }
  if (SDL_UpdateTexture(texture_, nullptr, image.rgba.data(), image.width * 4) != 0) sdl_fail("cannot upload a frame");
  SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 255);
  SDL_RenderClear(renderer_);
  if (SDL_RenderCopy(renderer_, texture_, nullptr, nullptr) != 0) sdl_fail("cannot draw a frame");
}

softpbr::raster::Image8 SdlWindow::read_back() {
  softpbr::raster::Image8 image;
  image.width = width();
  image.height = height();
  image.rgba.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4);
  if (SDL_RenderReadPixels(renderer_, nullptr, SDL_PIXELFORMAT_RGBA32, image.rgba.data(), image.width * 4) != 0)
    sdl_fail("cannot read the window's pixels");
  return image;
}

void SdlWindow::present() { SDL_RenderPresent(renderer_); }

void SdlWindow::set_title(const std::string& title) { SDL_SetWindowTitle(window_, title.c_str()); }

}  // namespace viewer
