// colosim bench render: frame time of the onboard and global views at 640 x 480 with the
// full adult colon, headless under OSMesa (llvmpipe). A frame is what the trainer pays:
// mesh rebuild from the control points, upload, draw, and glReadPixels (which waits for
// the frame to finish, glFinish).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <vector>

#include "bench/registry.h"
#include "bench/timing.h"
#include "render/offscreen_context.h"
#include "render/renderer.h"
#include "trainer/assets.h"

namespace colosim {

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the whole process, llvmpipe's rasteriser threads included [ms]: the work a
// frame takes, less sensitive than wall time to other jobs sharing the machine.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

// The scope along the colon's centreline from the anus to rest arclength tip_s_m, and the
// onboard camera at its tip looking along the centreline.
void scopeAlong(const ColonModel& model, const Points& q, double tip_s_m, ScopeShape& scope,
                CameraPose& cam) {
  scope.centreline_m.clear();
  int tip_seg = 0;
  double tip_p = 0;
  for (int j = 0; j + 1 < model.n; ++j) {
    for (int k = 0; k < 4; ++k) {
      const double p = k / 4.0;
      if (model.arclengthAt(j, p) > tip_s_m) break;
      scope.centreline_m.push_back(splinePoint(q, j, p));
      tip_seg = j, tip_p = p;
    }
  }
  const Vec3 tip = splinePoint(q, tip_seg, tip_p);
  cam = lookAlong(tip, splineTangent(q, tip_seg, tip_p), Vec3::UnitY());
}

}  // namespace

BenchOutput benchRender() {
  const int W = 640, H = 480, warmup = 5, frames = 61;
  const Parameters params = loadParameters(assetPath("params/default.json"));
  const ColonModel model = loadColonModel(assetPath("anatomy/adult.json"), params);
  OffscreenContext ctx(W, H);
  Renderer renderer;
  ScopeShape scope;
  CameraPose cam;
  // The tip in the descending colon, 0.45 m in (past the sigmoid): a long view ahead.
  scopeAlong(model, model.q_rest, 0.45, scope, cam);

  // The control points move a little every frame, as they would under the simulation,
  // so nothing can be reused between frames.
  Points q = model.q_rest;
  auto wiggle = [&](int f) {
    for (int i = 0; i < model.n; ++i) q(0, i) = model.q_rest(0, i) + 1e-4 * std::sin(0.1 * f + 0.3 * i);
  };
  std::vector<double> onboard_ms, onboard_cpu_ms, rectilinear_ms, global_ms, mesh_ms;
  OnboardOptics rectilinear;  // the same view without the barrel-distortion pass
  // Read back into images kept between frames, as the trainer's exports do.
  Image img, img2;
  rectilinear.barrel_distortion = false;
  for (int f = 0; f < warmup + frames; ++f) {
    wiggle(f);
    const double c0 = processCpuMs();
    const auto t0 = Clock::now();
    renderer.drawOnboard(model, q, scope, cam, Viewport{0, 0, W, H});
    ctx.read(img);
    const auto t1 = Clock::now();
    const double c1 = processCpuMs();
    renderer.drawOnboard(model, q, scope, cam, Viewport{0, 0, W, H}, rectilinear);
    ctx.read(img2);
    const auto t2 = Clock::now();
    if (f >= warmup) {
      onboard_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      onboard_cpu_ms.push_back(c1 - c0);
      rectilinear_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    }
  }
  const OrbitCamera orbit = frameBox(model.q_rest.rowwise().minCoeff(), model.q_rest.rowwise().maxCoeff(),
                                     static_cast<double>(W) / H);
  for (int f = 0; f < warmup + frames; ++f) {
    wiggle(f);
    const auto t0 = Clock::now();
    renderer.drawGlobal(model, q, scope, orbit, W, H);
    ctx.read(img);
    const auto t1 = Clock::now();
    if (f >= warmup) global_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  // The pure-data part alone: sampling the spline, frames, vertices, normals.
  TubeMesh mesh;
  for (int f = 0; f < warmup + frames; ++f) {
    wiggle(f);
    const auto t0 = Clock::now();
    buildColonMesh(model, q, renderer.tubeOptions(), mesh);
    const auto t1 = Clock::now();
    if (f >= warmup) mesh_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  const std::vector<unsigned> errors = drainGlErrors();
  if (!errors.empty()) throw std::runtime_error("bench render: GL error " + std::to_string(errors[0]));

  const double on_cpu = median(onboard_cpu_ms);
  const double on = median(onboard_ms), rect = median(rectilinear_ms), gl = median(global_ms),
               me = median(mesh_ms);
  const size_t triangles = mesh.indices.size() / 3;
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "render, adult colon (%d control points, %zu wall triangles), OSMesa llvmpipe, %d x %d,\n"
                "median of %d frames (mesh rebuild + upload + draw + glReadPixels):\n"
                "  onboard view: %7.2f ms per frame (%.0f fps); CPU time, all threads: %.2f ms\n"
                "    without barrel distortion: %7.2f ms per frame (%.0f fps)\n"
                "  global view:  %7.2f ms per frame (%.0f fps)\n"
                "  of which colon mesh rebuild: %.2f ms\n",
                model.n, triangles, W, H, frames, on, 1000 / on, on_cpu, rect, 1000 / rect, gl, 1000 / gl,
                me);
  BenchOutput out;
  out.json = {{"benchmark", "render"},
              {"width_px", W},
              {"height_px", H},
              {"frames", frames},
              {"colon_triangles", triangles},
              {"onboard_640x480_ms", on},
              {"onboard_640x480_cpu_ms", on_cpu},
              {"onboard_640x480_rectilinear_ms", rect},
              {"global_640x480_ms", gl},
              {"mesh_rebuild_ms", me}};
  out.text = buf;
  return out;
}

}  // namespace colosim
