// The Renderer (see renderer.h).
#include "softpbr/raster/renderer.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "softpbr/check.h"
#include "softpbr/simd/dispatch.h"
#include "softpbr/simd/simd.h"

// detail::{baseline, avx2, avx512}::fill_block().
#define SOFTPBR_TARGET_FILE "renderer-inl.h"
#include "softpbr/simd/foreach_target.h"

namespace softpbr::raster {

namespace detail {
namespace {
// renderer-inl.h's fill_block in the copy for `isa`.
auto fill_block_for(simd::Isa isa) { return SOFTPBR_DISPATCH(isa, fill_block); }
// A tile block's clear.
void fill_block(simd::Isa isa, const TargetPixels& block, const ClearValues& clear) {
  fill_block_for(isa)(block.colors, block.plane * static_cast<std::size_t>(block.samples), clear.color,
                      block.depths, depth_count(block.width, block.height, block.samples), clear.depth);
}
}  // namespace
}  // namespace detail

namespace {
int checked_tile_size(int tile) {
  if (!valid_tile_size(tile))
    throw std::invalid_argument("Renderer: tile size " + std::to_string(tile) + " must be even and in [" +
                                std::to_string(kMinTileSize) + ", " + std::to_string(kMaxTileSize) + "]");
  return tile;
}
// A tile's depths as runs of consecutive floats, fn(y, count): the run starting at pixel
// (r.x0, y) — a row of pixels, or with MSAA a row of 2×2 quads (raster::depth_index; tile
// origins are even, so a block's runs and the target's cover the same pixels).
template <class Fn>
void for_depth_runs(int samples, const TileRect& r, Fn&& fn) {
  const std::size_t width = static_cast<std::size_t>(r.x1 - r.x0);
  const int step = samples == 1 ? 1 : 2;
  const std::size_t count = samples == 1 ? width : (width + 1) / 2 * 4 * static_cast<std::size_t>(samples);
  for (int y = r.y0; y < r.y1; y += step) fn(y, count);
}
// Clears a tile. A tile no triangle touches is written with streaming stores (simd.h):
// nothing will read it soon, so it need not be fetched into the cache first. With AVX-512
// a touched tile's rows are written by fill_block's 64-byte stores (std::fill writes 16
// bytes at a time; the clear was 9% of a 1-thread gallery16 frame at 1×, and this took
// gallery16 and gallery64 at 1× 2.6% faster on a Zen 4); the AVX2 copy measured no gain
// (+2%, within the noise), so the other targets keep std::fill.
void clear_tile(simd::Isa isa, const TargetPixels& target, const TileRect& r, const ClearValues& clear,
                bool streaming) {
  const auto fill = isa == simd::Isa::Avx512 ? detail::fill_block_for(isa) : nullptr;
  const float color[4] = {clear.color.r, clear.color.g, clear.color.b, clear.color.a};
  const std::size_t n = static_cast<std::size_t>(r.x1 - r.x0);
  for (int s = 0; s < (target.colors != nullptr ? target.samples : 0); ++s) {  // each sample plane (target.h); none: depth only
    glm::vec4* colors = target.colors + static_cast<std::size_t>(s) * target.plane;
    for (int y = r.y0; y < r.y1; ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(target.width);
      if (streaming) {
        simd::stream_fill4(reinterpret_cast<float*>(colors + row + r.x0), color, n);
      } else if (fill != nullptr) {
        fill(colors + row + r.x0, n, clear.color, nullptr, 0, clear.depth);
      } else {
        std::fill(colors + row + r.x0, colors + row + r.x1, clear.color);
      }
    }
  }
  for_depth_runs(target.samples, r, [&](int y, std::size_t count) {
    float* depths = target.depths + target.depth_index(r.x0, y, 0);
    if (fill != nullptr) fill(nullptr, 0, clear.color, depths, count, clear.depth);
    else std::fill_n(depths, count, clear.depth);
  });
  if (streaming) simd::stream_fence();
}
// MSAA: in the pass that clears the frame, a touched tile's samples are rasterized in a
// block of the thread's own, not in the target's planes (target.h, TargetPixels): the
// block is cleared in cache and written to the target once, with streaming stores, when
// the tile is done, so the target's lines are never read for ownership; the tile
// callback resolves from the block, still in cache. Later passes of a frame (over the
// geometry budget) draw into the target itself: loading a block would read it anyway.
// Tiles of more samples than this (a 64-pixel tile at 8×: 32768, 640 KB) are rasterized
// in the target itself: a larger block would not stay in cache, and each pool thread keeps
// its block for the next frame.
constexpr std::size_t kMaxBlockSamples = 64 * 64 * 8;
struct TileBlock {
  std::vector<glm::vec4> colors;
  std::vector<float> depths;
};
TargetPixels tile_block(TileBlock& block, const TargetPixels& target, const TileRect& r) {
  const std::size_t w = static_cast<std::size_t>(r.x1 - r.x0), h = static_cast<std::size_t>(r.y1 - r.y0);
  const std::size_t n = w * h * static_cast<std::size_t>(target.samples);
  const std::size_t depths = depth_count(static_cast<int>(w), static_cast<int>(h), target.samples);
  if (block.colors.size() < n) block.colors.resize(n);
  if (block.depths.size() < depths) block.depths.resize(depths);
  return {block.colors.data(), block.depths.data(), static_cast<int>(w), static_cast<int>(h), target.samples, w * h,
          static_cast<std::size_t>(r.y0) * w + static_cast<std::size_t>(r.x0), r.x0, r.y0};
}
// Writes a tile's block into the target's sample planes with streaming stores.
void store_tile(const TargetPixels& block, const TileRect& r, const TargetPixels& target) {
  const std::size_t n = static_cast<std::size_t>(r.x1 - r.x0);
  for (int s = 0; s < target.samples; ++s)
    for (int y = r.y0; y < r.y1; ++y) {
      const std::size_t at = static_cast<std::size_t>(s) * target.plane +
                             static_cast<std::size_t>(y) * static_cast<std::size_t>(target.width) +
                             static_cast<std::size_t>(r.x0);
      const std::size_t bt = static_cast<std::size_t>(s) * block.plane + static_cast<std::size_t>(y - r.y0) * n;
      simd::stream_copy(target.colors + at, block.colors + bt, n * sizeof(glm::vec4));
    }
  for_depth_runs(target.samples, r, [&](int y, std::size_t count) {
    simd::stream_copy(target.depths + target.depth_index(r.x0, y, 0), block.depths + block.depth_index(r.x0, y, 0),
                      count * sizeof(float));
  });
  simd::stream_fence();
}
int checked_lanes(int lanes, simd::Isa isa) {
  if (lanes == 0) return isa == simd::Isa::Avx512 ? 16 : isa == simd::Isa::Avx2 ? 8 : simd::kNativeWidth;
  if (lanes != 1 && lanes != 4 && lanes != 8 && lanes != 16)
    throw std::invalid_argument("Renderer: lanes " + std::to_string(lanes) + " must be 0, 1, 4, 8 or 16");
  return lanes;
}
// Whether the two are the same bits (a tile cleared to one holds the other's pixels).
bool same_bits(const glm::vec4& color_a, float depth_a, const glm::vec4& color_b, float depth_b) {
  return std::memcmp(&color_a, &color_b, sizeof color_a) == 0 && std::memcmp(&depth_a, &depth_b, sizeof depth_a) == 0;
}
}  // namespace

Renderer::Renderer(RendererOptions options)
    : pool_(options.threads),
      tile_size_(checked_tile_size(options.tile_size)),
      isa_(options.dispatch ? simd::cpu_isa() : simd::Isa::Baseline),
      lanes_(checked_lanes(options.lanes, isa_)),
      geometry_budget_(options.geometry_budget),
      cancel_(std::move(options.cancel)) {}

Renderer::~Renderer() = default;

namespace {
// The tiles in the order a frame hands them to the pool: the grid's rows cut into one band
// per thread, and the bands' tiles (each band's in row-major order) taken in turn. Tiles
// handed out one after the other are drawn at the same time by different threads. Side by
// side, in row-major order, they contended for memory at their common edge (each tile row
// of the target ends where the neighbour's begins; aligning the target to cache lines did
// not help, so the hardware prefetchers running past the edge are the likely rest):
// fill8x_1080p on two threads of a Zen 5 ran only 1.3x faster than on one, and not at all
// faster with 16-pixel tiles. In bands: 0.66x the two-thread time (1.9x over one thread),
// the textured fill 0.84x, the IBL gallery 0.90x. Which thread draws a tile does not change
// its pixels (one writer per tile), so the order changes no bit.
void tile_order(const TileGrid& grid, unsigned threads, std::vector<std::uint32_t>& order) {
  const std::size_t count = grid.count();
  order.clear();  // its memory is kept from frame to frame
  const unsigned bands = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(grid.rows)));
  std::vector<std::size_t> next(bands), end(bands);
  for (unsigned b = 0; b < bands; ++b) {
    next[b] = static_cast<std::size_t>(grid.rows) * b / bands * static_cast<std::size_t>(grid.columns);
    end[b] = static_cast<std::size_t>(grid.rows) * (b + 1) / bands * static_cast<std::size_t>(grid.columns);
  }
  while (order.size() < count)
    for (unsigned b = 0; b < bands; ++b)
      if (next[b] < end[b]) order.push_back(static_cast<std::uint32_t>(next[b]++));
}
}  // namespace

void Renderer::begin_frame(Target& target) {
  if (!target_ && target.transient())
    throw std::logic_error("Renderer::begin_frame: a transient target holds nothing to draw over; clear it "
                           "(begin_frame(target, clear))");
  open_frame(target);
}

void Renderer::open_frame(Target& target) {
  if (target_) throw std::logic_error("Renderer::begin_frame: a frame is already open");
  target_ = &target;
  frame_budget_ = geometry_budget_;
  grid_ = TileGrid(target.width(), target.height(), tile_size_);
  grid_.sample_reach = sample_reach(target.samples());
  draws_.clear();
  clear_.reset();
  pending_bytes_ = 0;
  cleared_ = false;
  cancelled_.store(false, std::memory_order_relaxed);
  shaded_invocations_.store(0, std::memory_order_relaxed);
  shader_calls_.store(0, std::memory_order_relaxed);
  touched_.assign(grid_.count(), 0);
  tile_order(grid_, pool_.size(), tile_order_);
  // The frame may write any pixel: the target knows nothing until end_frame() says again.
  known_clear_ = detail::FrameAccess::take_cleared_tiles(target);
  if (known_clear_.tile_size != tile_size_ || known_clear_.tiles.size() != grid_.count()) known_clear_.tiles.clear();
}

void Renderer::begin_frame(Target& target, const ClearValues& clear) { begin_frame(target, clear, 0); }

void Renderer::begin_frame(Target& target, const ClearValues& clear, std::size_t geometry) {
  open_frame(target);
  clear_ = clear;
  if (geometry_budget_ != 0 && target.transient() && geometry > geometry_budget_) {
    const auto planes = static_cast<std::size_t>(Target::bytes(target.width(), target.height(), target.samples()));
    const std::size_t one_pass = std::min(planes, kTransientBudgetFactor * geometry_budget_);
    if (geometry <= one_pass) frame_budget_ = one_pass;
  }
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

void Renderer::flush(const TileCallback& after_tile) {
  if (!target_) throw std::logic_error("Renderer::flush: no frame is open");
  rasterize_pending(*target_, after_tile ? &after_tile : nullptr, false);
  frame_budget_ = geometry_budget_;  // the target's planes exist now: the usual passes
}

void Renderer::end_frame(const TileCallback& after_tile) {
  if (!target_) throw std::logic_error("Renderer::end_frame: no frame is open");
  Target& target = *target_;
  target_ = nullptr;
  rasterize_pending(target, after_tile ? &after_tile : nullptr, true);
  if (cancelled_.load(std::memory_order_relaxed)) {
    // Skipped tiles hold anything: the target knows of no cleared tile.
    cancelled_.store(false, std::memory_order_relaxed);
    known_clear_ = {};
    clear_.reset();
    throw Cancelled();
  }
  // Tell the target which tiles hold only clear values now: the untouched ones, if this
  // frame cleared (to its values), else those that did before and stayed untouched.
  detail::ClearedTiles& known = known_clear_;
  if (target.transient() && !planes_written_) {
    known = {};  // drawn in blocks alone: the planes, if any, hold an older frame
  } else if (clear_) {
    known.tile_size = tile_size_;
    known.color = clear_->color;
    known.depth = clear_->depth;
    known.tiles.resize(grid_.count());
    for (std::size_t t = 0; t < grid_.count(); ++t) known.tiles[t] = touched_[t] == 0;
  } else {
    for (std::size_t t = 0; t < known.tiles.size(); ++t) known.tiles[t] = known.tiles[t] && touched_[t] == 0;
  }
  detail::FrameAccess::set_cleared_tiles(target, std::move(known));
  known_clear_ = {};
  clear_.reset();
}

void Renderer::rasterize_pending(Target& target, const TileCallback* after_tile, bool last_pass) {
  const bool clear_now = clear_ && !cleared_;
  // Tiles that hold the clear values already (the target's last frame cleared to the same
  // bits and left them untouched) are not cleared again: the same pixels, no writes.
  const bool reuse = clear_now && !known_clear_.tiles.empty() &&
                     same_bits(known_clear_.color, known_clear_.depth, clear_->color, clear_->depth);
  // A transient target (SampleStorage::Transient) is drawn in blocks alone when the frame
  // is one pass that clears and every tile fits a block: nothing reaches its planes, not
  // even the clear of untouched tiles. Otherwise its planes are allocated and the frame
  // runs as for a kept target (a later pass draws over what the first left there).
  const std::size_t tile_samples = static_cast<std::size_t>(tile_size_) * static_cast<std::size_t>(tile_size_) *
                                   static_cast<std::size_t>(target.samples());
  const bool blocks_only = target.transient() && clear_now && last_pass && tile_samples <= kMaxBlockSamples;
  if (target.transient() && !blocks_only) detail::FrameAccess::allocate_planes(target);
  planes_written_ = !blocks_only;
  const TargetPixels pixels = detail::FrameAccess::pixels(target);
  if (!draws_.empty() || clear_now || after_tile) {
    pool_.parallel_for(grid_.count(), [&](std::size_t i) {
      const std::size_t tile = tile_order_[i];
      if (cancel_ && (cancelled_.load(std::memory_order_relaxed) || cancel_())) {
        cancelled_.store(true, std::memory_order_relaxed);
        return;
      }
      const TileRect rect = grid_.rect(tile);
      bool touched = false;
      for (const auto& draw : draws_) touched = touched || draw->geometry.touches(tile);
      const bool in_block = clear_now && touched && pixels.samples > 1 &&
                            static_cast<std::size_t>(rect.x1 - rect.x0) * static_cast<std::size_t>(rect.y1 - rect.y0) *
                                    static_cast<std::size_t>(pixels.samples) <=
                                kMaxBlockSamples;
      if (clear_now && !in_block && !blocks_only && !(reuse && known_clear_.tiles[tile] != 0 && !touched))
        clear_tile(isa_, pixels, rect, *clear_, !touched);
      thread_local TileBlock block;
      TargetPixels tile_pixels = pixels;  // what the callback reads: the block or the target
      ShadeCounts shaded;
      if (in_block) {
        tile_pixels = tile_block(block, pixels, rect);
        detail::fill_block(isa_, tile_pixels, *clear_);
        for (const auto& draw : draws_) shaded += draw->raster(tile, rect, tile_pixels, lanes_, isa_);
        if (!blocks_only) store_tile(tile_pixels, rect, pixels);
        touched_[tile] = 1;  // one writer per tile
      } else if (touched) {
        SOFTPBR_DCHECK(tile < touched_.size());
        for (const auto& draw : draws_) shaded += draw->raster(tile, rect, pixels, lanes_, isa_);
        touched_[tile] = 1;  // one writer per tile
      }
      if (shaded.calls != 0) {
        shaded_invocations_.fetch_add(shaded.invocations, std::memory_order_relaxed);
        shader_calls_.fetch_add(shaded.calls, std::memory_order_relaxed);
      }
      if (after_tile) (*after_tile)(rect, clear_.has_value() && touched_[tile] == 0, tile_pixels);
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
