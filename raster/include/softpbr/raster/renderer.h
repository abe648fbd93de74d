// softpbr/raster/renderer.h — the Renderer: frames of draws, on a pool of threads.
//
//   softpbr::raster::Renderer renderer({.threads = 0, .tile_size = 64});
//   softpbr::raster::Target target(640, 480);
//   renderer.begin_frame(target, softpbr::raster::ClearValues{{0, 0, 0, 1}, 1.0f});
//   renderer.draw(my_shader, vertices, indices);        // any number, any shader types
//   renderer.end_frame();                               // rasterizes every tile
//
// draw() runs the vertex stage, clipping, setup and binning at once (in parallel) and
// keeps a copy of the shader; end_frame() rasterizes the tiles in parallel, each tile on
// one thread, each tile's triangles in submission order across all draws of the frame.
// The image is bit-identical for every thread count and tile size.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "softpbr/raster/detail/bin.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/detail/rast.h"
#include "softpbr/raster/shader.h"
#include "softpbr/raster/target.h"
#include "softpbr/raster/detail/vertex.h"

namespace softpbr::raster {

struct RendererOptions {
  unsigned threads = 0;  // 0: all hardware threads; 1: everything inline on the caller
  int tile_size = 64;    // even, in [kMinTileSize, kMaxTileSize]
  // Pixels per fragment_packet() call for packet shaders, at most: 1, 4, 8 or 16; 0 picks
  // the widest this CPU runs natively (16 with AVX-512 and 8 with AVX2 when `dispatch` is
  // on, else simd::kNativeWidth of the build). A width wider than the instruction set's
  // registers runs the widest kernel compiled that fits (16 on AVX2: 8 lanes; 8 or 16
  // without dispatch in a baseline x86-64 or AArch64 build: 4). Any width gives the same bits.
  int lanes = 0;
  // Run packet kernels compiled for the CPU's widest instruction set (runtime dispatch,
  // simd.h: AVX2 for 8 lanes, AVX-512 for 16) when it has one; false: the build's own
  // code only. The same bits either way.
  bool dispatch = true;
  // Bytes of binned geometry (transformed vertices, set-up triangles, tile lists) a frame
  // may hold: past it, draw() rasterizes the draws so far into the tiles and recycles
  // their memory, so peak memory stays bounded however many triangles a frame has. The
  // same bits either way (each tile still applies every draw in order). 0: no limit.
  // A frame on a transient target (SampleStorage::Transient) told its geometry may be
  // drawn in one pass of up to 4 times as much (see begin_frame).
  std::size_t geometry_budget = std::size_t{8} << 20;
  // Polled before each tile of a frame is rasterized, on the thread about to draw it (so
  // calls may run at the same time): once it returns true, the frame's remaining tiles are
  // skipped and end_frame() throws Cancelled — the target's pixels are then unspecified and
  // the renderer is ready for another frame. For stopping long renders (Ctrl-C in the
  // Python module). Empty: never polled. A frame it lets finish has the same bits.
  std::function<bool()> cancel = nullptr;
};

// end_frame() stopped early because RendererOptions::cancel returned true.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("render cancelled") {}
};

// What begin_frame() clears the target to.
struct ClearValues {
  glm::vec4 color{0.0f, 0.0f, 0.0f, 1.0f};
  float depth = 1.0f;
};

inline constexpr int kMinTileSize = 8;
inline constexpr int kMaxTileSize = 4096;

// Whether the Renderer accepts `tile` as its tile size: in [kMinTileSize, kMaxTileSize] and
// even, so that a tile holds whole 2×2 quads.
constexpr bool valid_tile_size(int tile) { return tile >= kMinTileSize && tile <= kMaxTileSize && tile % 2 == 0; }

// Bytes a draw of `vertices` vertices and `triangles` triangles, `varyings` floats per
// vertex, holds until its frame is rasterized, for estimates made before drawing (a scene
// loader's memory budget): per vertex the arrays of TransformedVertices (clip position,
// varyings, outcode, screen vertex), per triangle the set-up Triangle and four tile-list
// entries (a small triangle may straddle four tiles). Derived from the types, so the
// estimate follows them; vector growth slack and vertices made by clipping are not counted.
constexpr std::size_t draw_geometry_bytes(std::size_t vertices, std::size_t triangles, int varyings) {
  using V = TransformedVertices;
  constexpr std::size_t kTileEntriesPerTriangle = 4;
  const std::size_t per_vertex = sizeof(decltype(V::position)::value_type) +
                                 static_cast<std::size_t>(varyings) * sizeof(decltype(V::values)::value_type) +
                                 sizeof(decltype(V::outcode)::value_type) + sizeof(decltype(V::screen)::value_type);
  const std::size_t per_triangle = sizeof(decltype(TriangleChunk::triangles)::value_type) +
                                   kTileEntriesPerTriangle * sizeof(decltype(TriangleChunk::list)::value_type);
  return vertices * per_vertex + triangles * per_triangle;
}

class Renderer {
 public:
  // Throws std::invalid_argument for a tile size that is odd or out of range.
  explicit Renderer(RendererOptions options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  unsigned threads() const { return pool_.size(); }
  // The threads RendererOptions::threads asked for; more than threads() when the system
  // refused to start some (the renderer then runs with those it got: the same images).
  unsigned requested_threads() const { return pool_.requested(); }
  int lanes() const { return lanes_; }
  // The instruction set the packet kernels run with (Baseline: the build's own).
  simd::Isa isa() const { return isa_; }
  int tile_size() const { return tile_size_; }
  // The renderer's threads, for work outside frames that should use them too (building a
  // Texture's mip chain). Not to be used from inside a draw's shader.
  ThreadPool& pool() { return pool_; }

  // Starts a frame on `target`, which must outlive end_frame(). Throws std::logic_error
  // if a frame is already open. The first form draws over the target's contents (and
  // throws std::logic_error for a transient target, which has none); the second clears it
  // (each tile just before it is rasterized, in parallel: cheaper than Target::clear()).
  // A tile that the target's last frame left holding only the same clear values (bit for
  // bit), untouched since (see Target), is not written again.
  void begin_frame(Target& target);
  void begin_frame(Target& target, const ClearValues& clear);
  // The same, told the bytes of geometry the frame's draws will bin (draw_geometry_bytes
  // summed over them). For a transient target, a frame over the geometry budget that will
  // hold at most 4 times it, and no more than the target's samples would take
  // (Target::bytes), is drawn in one pass, so the target needs no planes. Other targets,
  // and frames that hold more (where one larger pass measured slower than passes over
  // planes), pass at the budget as usual. An estimate off either way changes no bit.
  void begin_frame(Target& target, const ClearValues& clear, std::size_t geometry);

  // Draws indexed triangles (three indices each). Throws std::logic_error outside a
  // frame, std::invalid_argument for a shader that is not depth-only on a depth-only
  // target or a depth-only one on a multisampled target (shader.h, kDepthOnly), if
  // indices.size() is not a multiple of 3 and
  // std::out_of_range for an index past the vertices; nothing is drawn then.
  template <Shader S>
  void draw(const S& shader, std::span<const typename S::Vertex> vertices, std::span<const std::uint32_t> indices,
            const DrawState& state = {}) {
    require_frame();
    if constexpr (kDepthOnly<S>) {
      if (target_->samples() != 1) throw std::invalid_argument("Renderer::draw: a depth-only shader draws into a 1-sample target");
    } else {
      if (target_->is_depth_only())
        throw std::invalid_argument("Renderer::draw: a depth-only target takes depth-only shaders (raster::kDepthOnly)");
    }
    validate_indices(indices, vertices.size());
    auto call = std::make_unique<TypedDrawCall<S>>(shader);
    call->geometry = take_geometry();
    call->geometry.state = state;
    if (state.alpha_to_coverage) call->geometry.state.alpha_test = true;
    run_vertex_stage(pool_, call->shader, vertices, Viewport{grid_.width, grid_.height}, call->geometry.vertices);
    assemble_triangles(pool_, indices, grid_, call->geometry);
    pending_bytes_ += call->geometry.bytes();
    draws_.push_back(std::move(call));
    if (frame_budget_ != 0 && pending_bytes_ > frame_budget_) {
      rasterize_pending(*target_, nullptr, false);
      frame_budget_ = geometry_budget_;  // the target's planes exist now: the usual passes (if raised)
    }
  }

  // Draws vertices 3k, 3k+1, 3k+2 as triangle k; the count must be a multiple of 3.
  template <Shader S>
  void draw(const S& shader, std::span<const typename S::Vertex> vertices, const DrawState& state = {}) {
    if (vertices.size() > std::numeric_limits<std::uint32_t>::max())
      throw std::length_error("Renderer::draw: more than 2^32 - 1 vertices");
    std::vector<std::uint32_t> indices(vertices.size());  // validated: a multiple of 3
    std::iota(indices.begin(), indices.end(), 0u);
    draw(shader, vertices, indices, state);
  }

  // Rasterizes the frame's draws so far into every tile, the frame staying open (later
  // draws apply over them, as a pass over the geometry budget does), calling
  // after_tile(rect, only_clear, pixels) for every tile as end_frame() does: for a copy
  // of what those draws left (pbr::render's transmission reads the opaque objects' image).
  // A transient target's planes are allocated for such a frame. The same bits as without
  // the flush. Throws std::logic_error outside a frame.
  using TileCallback = std::function<void(const TileRect& rect, bool only_clear, const TargetPixels& pixels)>;
  void flush(const TileCallback& after_tile);

  // Rasterizes the frame's draws into the target and closes the frame.
  void end_frame();

  // The same, calling after_tile(rect, only_clear, pixels) for every tile of the frame, on
  // the thread that drew it, as soon as its last draw is done: to resolve or tone map the
  // tile while it is in cache. only_clear is true when the frame cleared and no triangle
  // came near the tile: every pixel holds the clear values. `pixels` holds the tile's
  // pixels as the target does (read them there rather than from the target: a
  // multisampled tile's samples are rasterized in a block of the thread's own and reach
  // the target with streaming stores, so the block is still in cache and the target's
  // copy is not); it is valid during the call only. Calls for different tiles may run at
  // the same time; each tile's pixels belong to its call alone until end_frame() returns.
  // A transient target (SampleStorage::Transient) is read here or nowhere; when its frame
  // is drawn in blocks alone, an only_clear tile has no pixels anywhere (pixels.colors and
  // pixels.depths are null): the clear values are its contents.
  void end_frame(const TileCallback& after_tile);

  // What the last frame shaded (since begin_frame(); complete once end_frame() returns):
  // fragment-shader invocations, as GL's pipeline statistics count them (one per pixel a
  // triangle covers and that passes the depth test; with MSAA one per pixel and triangle,
  // whatever number of its samples the triangle covers), and the shader calls that
  // shaded them (fragment() once per pixel, fragment_packet() once per packet of up to
  // lanes() pixels, so invocations / (calls · lanes()) is how full the packets were).
  // Invocations are the same for any thread count, tile size and lane width.
  ShadeCounts frame_shading() const {
    return {shaded_invocations_.load(std::memory_order_relaxed), shader_calls_.load(std::memory_order_relaxed)};
  }

 private:
  struct DrawCall {
    virtual ~DrawCall() = default;
    // One virtual call per draw and tile; the shader inlines inside.
    virtual ShadeCounts raster(std::size_t tile, const TileRect& rect, const TargetPixels& target, int lanes,
                               simd::Isa isa) const = 0;
    DrawGeometry geometry;
  };
  template <Shader S>
  struct TypedDrawCall final : DrawCall {
    explicit TypedDrawCall(const S& s) : shader(s) {}
    ShadeCounts raster(std::size_t tile, const TileRect& rect, const TargetPixels& target, int lanes,
                       simd::Isa isa) const override {
      return raster_tile(shader, this->geometry, tile, rect, target, lanes, isa);
    }
    S shader;
  };

  void require_frame() const;
  DrawGeometry take_geometry();
  // Rasterizes the pending draws into every tile (clearing first if the frame clears and
  // has not cleared yet), calls after_tile if given, and recycles their geometry.
  // last_pass: called by end_frame() (not by a draw over the geometry budget), so no later
  // pass of the frame reads what it leaves.
  void rasterize_pending(Target& target, const TileCallback* after_tile, bool last_pass);
  void open_frame(Target& target);

  ThreadPool pool_;
  int tile_size_;
  simd::Isa isa_;
  int lanes_;
  Target* target_ = nullptr;
  TileGrid grid_;
  std::vector<std::unique_ptr<DrawCall>> draws_;
  std::optional<ClearValues> clear_;
  std::vector<DrawGeometry> spare_;  // geometry of past draws, kept for their memory
  std::size_t geometry_budget_;
  // This frame's pass: geometry_budget_, or for a transient target's frame told it fits, up
  // to kTransientBudgetFactor times as much (begin_frame's geometry).
  std::size_t frame_budget_ = 0;
  static constexpr std::size_t kTransientBudgetFactor = 4;
  bool planes_written_ = false;  // whether the last pass wrote the target's planes (not blocks alone)
  std::function<bool()> cancel_;
  std::atomic<bool> cancelled_{false};  // the frame's cancel_ returned true (set by any tile's thread)
  std::size_t pending_bytes_ = 0;       // geometry held by draws_
  std::atomic<std::uint64_t> shaded_invocations_{0}, shader_calls_{0};  // the frame's (frame_shading())
  bool cleared_ = false;                // the frame's clear is done (by an earlier pass)
  std::vector<std::uint8_t> touched_;   // per tile: a triangle was rasterized into it
  // The order the pool's threads take the tiles in: tiles taken one after the other
  // (so drawn at the same time by different threads) lie in different bands of tile rows,
  // not side by side (see tile_order() in renderer.cpp).
  std::vector<std::uint32_t> tile_order_;
  // The target's cleared tiles as the frame found them (detail::ClearedTiles), taken out
  // of the target while the frame runs and given back, updated, by end_frame().
  detail::ClearedTiles known_clear_;
};

}  // namespace softpbr::raster
