// The renderer: one OpenGL 4.5 core renderer for the viewer's window and for headless frames.
//
// It sees only what the physics publishes (snapshot positions) and the model's static topology;
// it never calls into the simulator. All methods need the OpenGL context they
// were created in to be current on the calling thread; nothing here is thread-safe.
//
// What it draws, back to front:
//   background   a vertical grey gradient
//   grid         a floor grid under the scene, lowered when a point goes below it
//   surfaces     cloth faces, lit on both sides with per-vertex normals (front orange-red,
//                back golden)
//   links        segments coloured by strain |d| / rest - 1: grey at rest, red when stretched,
//                blue when compressed, saturated at +-strain_range
//   contacts     conditional links while active (distance below their threshold), yellow
//   points       masses not on a surface (grey-blue), fixed (dark) and driven (magenta) points
//   solids       the snapshot's surfaces (obstacles), in their own colour, translucent: after
//                everything opaque, far ones first, each inside then outside, not writing depth
//   overlay      segments given by the caller (the viewer's drag spring), always on top
#pragma once

#include <array>
#include <memory>
#include <span>
#include <vector>

#include "maille/model.hpp"
#include "maille/render/camera.hpp"
#include "maille/render/topology.hpp"
#include "maille/smooth_surface.hpp"
#include "maille/snapshot.hpp"

namespace maille::render {

struct RenderOptions {
  bool surface = true;            // cloth faces
  bool links = true;              // links not inside a cloth
  bool links_on_surface = false;  // also the links of a cloth's mesh (its structure)
  bool contacts = true;           // active conditional links
  bool points = true;             // masses off surfaces, fixed and driven points
  bool grid = true;               // floor grid
  bool solids = true;             // the snapshot's surfaces (obstacles)
  float strain_range = 0.05f;     // |strain| drawn fully red or blue, dimensionless, > 0
  float link_width = 2.0f;        // pixels, > 0
  float point_scale = 1.0f;       // times the topology's point radius, > 0
  // Draw cloth faces as a smooth surface through the particles (smooth_surface.hpp), evaluated
  // on the GPU by a compute shader: `smooth_lod` sub-segments per physical edge, 1 to 16.
  bool smooth = false;
  int smooth_lod = 4;
};

// A segment drawn on top of everything (overlays): see snapshot.hpp.
using OverlaySegment = maille::OverlaySegment;

class Renderer {
 public:
  // Compiles the shaders; throws std::runtime_error with the driver's log when it cannot.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // The model's topology and a floor grid under its initial positions. Call again after a
  // scene reload; the positions are reset to the initial ones.
  void set_model(const Model& model);
  // Positions and solids to draw. Throws std::invalid_argument when the snapshot's point count
  // differs from the model's (a stale snapshot from before a reload). A solid's mesh is uploaded
  // the first time its pointer is seen and freed with the first snapshot that no longer holds it.
  // A snapshot whose positions are on the device (Snapshot::device, a buffer of this context's
  // share group, ready to read) is drawn straight from that buffer until the next snapshot:
  // nothing is read back; normals, contacts and bounds are computed on the GPU.
  void set_snapshot(const Snapshot& snapshot);
  void set_overlay(std::span<const OverlaySegment> segments);

  // Draws into the framebuffer bound now, over a width x height viewport (pixels).
  void draw(const Camera& camera, int width, int height, const RenderOptions& options);

  const RenderTopology& topology() const { return topology_; }
  // The positions drawn (initial ones until the first snapshot), for picking and framing; with
  // device snapshots, the last host ones (device positions are never read back).
  std::span<const Vec3> positions() const { return positions_; }
  bool draws_device_positions() const { return device_positions_ != 0; }
  const Snapshot& snapshot_info() const { return info_; }  // frame, step, time; no positions
  // What framing should keep in view: the finite positions and the boxes of the closed solids
  // placed as in the last snapshot. Open ones (a ground plane's square) are left out: they
  // stand for unbounded surfaces, and their drawn size is arbitrary. With device snapshots, the
  // positions' box is a GPU reduction read once it is done (a frame or so late), never a copy.
  Bounds bounds() const;
  // Waits until bounds() includes the last device snapshot (the GPU's reduction done, 32 bytes
  // read): for offline rendering, whose framing must not lag. No effect on host snapshots.
  void wait_for_bounds();
  std::size_t solid_meshes() const;  // meshes on the GPU now (one per distinct pointer)
  // The smooth surface's vertices as the GPU last evaluated them (6 floats each: position,
  // normal; SmoothSurface's layout), read back: for tests against the CPU evaluation. Empty
  // before the first smooth draw.
  std::vector<float> smooth_vertices() const;
  // The vertex normals drawn (3 floats per point, computed on the GPU from the positions drawn),
  // read back: for tests against surface_normals.
  std::vector<float> normals() const;
  const SmoothSurface& smooth_surface() const { return smooth_; }

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  RenderTopology topology_;
  std::vector<Vec3> positions_;
  Snapshot info_;
  std::vector<float> scratch_xyz_;
  std::uint32_t device_positions_ = 0;  // the snapshot's device buffer drawn; 0: our own
  Bounds device_bounds_;                // the device positions' box, as last read
  Bounds grid_box_;                     // the grid lies under it, at its lowest height
  std::vector<OverlaySegment> overlay_;
  std::vector<SurfaceInstance> solids_;  // the last snapshot's surfaces
  SmoothSurface smooth_;                 // the model's faces as smooth patches
  void upload_positions();
  unsigned drawn_positions() const;  // the buffer the passes read positions from
  void positions_changed();          // normals (and a device's bounds) from the positions drawn
  void poll_device_bounds();         // the reduction's result, once the GPU has it
  void lower_grid(const Bounds& now);
  void upload_solids();  // meshes not seen before; frees those no longer held
  void draw_solids(const Camera& camera, const Mat4& view_proj, const Mat4& view);
  void upload_lines();           // grid and overlay
  void prepare_smooth(int lod);  // buffers for this level of detail (once per change)
  void draw_smooth(const Mat4& view_proj, const Mat4& view, int lod);
};

}  // namespace maille::render
