// The Renderer (see renderer.h).
#include "softpbr/raster/renderer.h"

#include <algorithm>
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
// Clears a tile. A tile no triangle touches is written with streaming stores (simd.h):
// nothing will read it soon, so it need not be fetched into the cache first.
void clear_tile(Target& target, const TileRect& r, const ClearValues& clear, bool streaming) {
  glm::vec4* colors = target.colors().data();
  float* depths = target.depths().data();
  const float color[4] = {clear.color.r, clear.color.g, clear.color.b, clear.color.a};
  const std::size_t n = static_cast<std::size_t>(r.x1 - r.x0);
  for (int y = r.y0; y < r.y1; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(target.width());
    if (streaming) {
      simd::stream_fill4(reinterpret_cast<float*>(colors + row + r.x0), color, n);
    } else {
      std::fill(colors + row + r.x0, colors + row + r.x1, clear.color);
    }
    std::fill(depths + row + r.x0, depths + row + r.x1, clear.depth);
  }
  if (streaming) simd::stream_fence();
}
int checked_lanes(int lanes, simd::Isa isa) {
  if (lanes == 0) return isa == simd::Isa::Avx512 ? 16 : isa == simd::Isa::Avx2 ? 8 : simd::kNativeWidth;
  if (lanes != 1 && lanes != 4 && lanes != 8 && lanes != 16)
    throw std::invalid_argument("Renderer: lanes " + std::to_string(lanes) + " must be 0, 1, 4, 8 or 16");
  return lanes;
}
}  // namespace

Renderer::Renderer(RendererOptions options)
    : pool_(options.threads),
      tile_size_(checked_tile_size(options.tile_size)),
      isa_(options.dispatch ? simd::cpu_isa() : simd::Isa::Baseline),
      lanes_(checked_lanes(options.lanes, isa_)),
      geometry_budget_(options.geometry_budget) {}

Renderer::~Renderer() = default;

void Renderer::begin_frame(Target& target) {
  if (target_) throw std::logic_error("Renderer::begin_frame: a frame is already open");
  target_ = &target;
  grid_ = TileGrid(target.width(), target.height(), tile_size_);
  draws_.clear();
  clear_.reset();
  pending_bytes_ = 0;
  cleared_ = false;
  touched_.assign(grid_.count(), 0);
}

void Renderer::begin_frame(Target& target, const ClearValues& clear) {
  begin_frame(target);
  clear_ = clear;
}

DrawGeometry Renderer::take_geometry() {
  if (spare_.empty()) return {};
  DrawGeometry g = std::move(spare_.back());
  spare_.pop_back();
  return g;
}

void Renderer::require_frame() const {
  if (!target_) throw std::logic_error("Renderer::draw: call begin_frame() first");
}

void Renderer::end_frame() { end_frame(nullptr); }

void Renderer::end_frame(const TileCallback& after_tile) {
  if (!target_) throw std::logic_error("Renderer::end_frame: no frame is open");
  Target& target = *target_;
  target_ = nullptr;
  rasterize_pending(target, after_tile ? &after_tile : nullptr);
  clear_.reset();
}

void Renderer::rasterize_pending(Target& target, const TileCallback* after_tile) {
  const bool clear_now = clear_ && !cleared_;
  if (!draws_.empty() || clear_now || after_tile) {
    pool_.parallel_for(grid_.count(), [&](std::size_t tile) {
      const TileRect rect = grid_.rect(tile);
      bool touched = false;
      for (const auto& draw : draws_) touched = touched || draw->geometry.touches(tile);
      if (clear_now) clear_tile(target, rect, *clear_, !touched);
      if (touched) {
        for (const auto& draw : draws_) draw->raster(tile, rect, target, lanes_, isa_);
        touched_[tile] = 1;  // one writer per tile
      }
      if (after_tile) (*after_tile)(rect, clear_.has_value() && touched_[tile] == 0);
    });
  }
  cleared_ = cleared_ || clear_now;
  for (auto& draw : draws_) {
    draw->geometry.recycle();
    spare_.push_back(std::move(draw->geometry));
  }
  draws_.clear();
  pending_bytes_ = 0;
}

}  // namespace softpbr::raster
