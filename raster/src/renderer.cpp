// The Renderer (see renderer.h).
#include "softpbr/raster/renderer.h"

#include <stdexcept>
#include <string>

namespace softpbr::raster {

namespace {
int checked_tile_size(int tile) {
  if (tile < kMinTileSize || tile > kMaxTileSize || tile % 2 != 0)
    throw std::invalid_argument("Renderer: tile size " + std::to_string(tile) + " must be even and in [" +
                                std::to_string(kMinTileSize) + ", " + std::to_string(kMaxTileSize) + "]");
  return tile;
}
}  // namespace

Renderer::Renderer(RendererOptions options)
    : pool_(options.threads), tile_size_(checked_tile_size(options.tile_size)) {}

Renderer::~Renderer() = default;

void Renderer::begin_frame(Target& target) {
  if (target_) throw std::logic_error("Renderer::begin_frame: a frame is already open");
  target_ = &target;
  grid_ = TileGrid(target.width(), target.height(), tile_size_);
  draws_.clear();
}

void Renderer::require_frame() const {
  if (!target_) throw std::logic_error("Renderer::draw: call begin_frame() first");
}

void Renderer::end_frame() {
  if (!target_) throw std::logic_error("Renderer::end_frame: no frame is open");
  Target& target = *target_;
  target_ = nullptr;
  if (!draws_.empty()) {
    pool_.parallel_for(grid_.count(), [&](std::size_t tile) {
      const TileRect rect = grid_.rect(tile);
      for (const auto& draw : draws_) draw->raster(tile, rect, target);
    });
  }
  draws_.clear();
}

}  // namespace softpbr::raster
