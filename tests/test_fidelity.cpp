// Fidelity against the references of ../shared/fidelity (fidelity/fidelity.h, the protocol
// of its README): model-only PSNR against Blender Cycles at 256 samples a pixel, and against
// three.js r187. Skipped cleanly when ../shared is not there; `build/tests/softpbr_fidelity`
// prints the same figures (README.md's table, docs/design.md "Image-based lighting").
//
// What is held: each model at least at the PSNR against Cycles this build reached when it
// was written, less 0.1 dB (a change that takes the shading further from the path tracer
// fails here), and at least 18 dB against three.js (the same family of renderer: no
// regression in look). The goal of issue 47 — three.js's PSNR + 1 dB on every model — is
// printed, met or not: met on NormalTangentMirrorTest; the others need more than this
// build's screen-space occlusion (the bottle's shaded side, the wide contact shadows of
// AlphaBlendModeTest) and the spheres' reflections of each other (MetalRoughSpheres).
#include <doctest/doctest.h>

#include <map>
#include <string>

#include "fidelity/fidelity.h"

using namespace softpbr;

TEST_CASE("fidelity: the reference models stay as close to Cycles as this build's floor, and near three.js") {
  const std::filesystem::path shared = fidelity::find_shared(SOFTPBR_SOURCE_DIR);
  if (shared.empty()) {
    MESSAGE("../shared/fidelity is not there: skipped");
    return;
  }
  // dB against Cycles, measured (before issue 47: 15.32, 17.85, 14.54, 19.99; with the
  // irradiance map, the specular levels and the dielectric diffuse weight, then screen-space
  // occlusion: see docs/design.md "Fidelity"); each floor is its figure less 0.1 dB.
  const std::map<std::string, double> floor = {{"WaterBottle", 16.81},
                                               {"MetalRoughSpheresNoTextures", 19.61},
                                               {"NormalTangentMirrorTest", 18.44},
                                               {"AlphaBlendModeTest", 20.15}};
  raster::Renderer renderer;
  for (const std::string& m : fidelity::models()) {
    CAPTURE(m);
    const fidelity::Result r = fidelity::measure(shared, m, renderer);
    const double goal = r.threejs_vs_cycles + 1.0;
    MESSAGE(m << ": vs Cycles " << r.vs_cycles << " dB (three.js " << r.threejs_vs_cycles << ", goal " << goal
              << (r.vs_cycles >= goal ? std::string(": met") : std::string(": not yet")) << "), vs three.js " << r.vs_threejs << " dB");
    CHECK(r.pixels > 1000);
    CHECK(r.vs_cycles >= floor.at(m));
    CHECK(r.vs_threejs >= 18.0);
  }
}
