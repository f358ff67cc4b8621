#include "engine/synth/render_view.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "engine/synth/snell.h"
#include "engine/synth/surface_intersect.h"
#include "engine/synth/synth_rng.h"

namespace refrax::synth {

namespace {

glm::dvec3 shadeSurface(const SynthScene& scene, const TriangleHit& hit, const glm::dvec3& dir) {
  const MeshTriangle& tri = scene.bvh.triangles[hit.triangle];
  double b0 = 1 - hit.b1 - hit.b2;
  glm::dvec2 uv = b0 * tri.uv[0] + hit.b1 * tri.uv[1] + hit.b2 * tri.uv[2];
  glm::dvec3 n = glm::normalize(b0 * tri.n[0] + hit.b1 * tri.n[1] + hit.b2 * tri.n[2]);
  if (glm::dot(n, dir) > 0) n = -n;  // two-sided: light the face the ray sees
  const SynthMaterial& m = scene.materials[tri.material];
  glm::dvec3 albedo = sampleBilinear(scene.textures[m.texture], uv.x * m.uvScale.x, uv.y * m.uvScale.y) * m.tint;
  double lambert = std::max(0.0, glm::dot(n, glm::normalize(scene.lightDirection)));
  return albedo * (scene.ambient + (1 - scene.ambient) * lambert);
}

}  // namespace

RayResult shadeCameraRay(const SynthScene& scene, const WaveSurface* water, double ior, const glm::dvec3& origin, const glm::dvec3& dir) {
  RayResult r{scene.background, false, false, {}};
  glm::dvec3 o = origin, d = dir;
  if (water) {
    auto crossing = intersectWaveSurface(*water, o, d);
    // A ray that enters the domain's box under the surface (through its side) crosses upward
    // first; like a ray outside the domain it goes on unrefracted and is masked.
    // Something dry beside the water (a rim) may stand between the camera and the water.
    if (crossing && scene.geometryAboveWater && closestTriangleHit(scene.bvh, o, d, 1e-9, crossing->t)) crossing.reset();
    if (crossing && crossing->downward) {
      glm::dvec3 p = o + crossing->t * d;
      auto refracted = refractDirection(d, waveNormal(*water, p.x, p.y), 1.0 / ior);
      if (refracted) {
        o = p;
        d = *refracted;
        r.metWater = true;
      }
    }
  }
  // The scene over the water lies strictly below the lowest trough, so after refraction no
  // second water crossing can come before it; the tiny tMin only skips the starting point. (A
  // rim's wall is the exception: a ray refracted near a crest may meet the wall above the
  // water there, which a real ray would reach only after leaving the water; such rays graze
  // the edge of the opening and are few.)
  auto hit = closestTriangleHit(scene.bvh, o, d, 1e-9, 1e30);
  if (hit) {
    r.colour = shadeSurface(scene, *hit, d);
    r.hitScene = true;
    r.scenePoint = o + hit->t * d;
  }
  return r;
}

RenderedView renderView(const SynthScene& scene, const WaveSurface* water, double ior, const SynthCamera& cam, const RenderSettings& settings,
                        uint64_t viewKey) {
  RenderedView out;
  out.width = cam.width;
  out.height = cam.height;
  out.rgb.assign(size_t(cam.width) * cam.height * 3, 0.0f);
  out.mask.assign(size_t(cam.width) * cam.height, 0.0f);
  const int n = std::max(1, settings.samplesPerAxis);
  const int threads = std::max(1, settings.threads);
  const glm::dmat4 worldToCamera = glm::inverse(cam.cameraToWorld);
  const glm::dvec3 eye = cameraCentre(cam);

  struct Partial {
    double nearDepth = 1e300, farDepth = -1e300;
    size_t missing = 0;
  };
  std::vector<Partial> partial(threads);
  auto work = [&](int t) {
    Partial& part = partial[t];
    for (int y = t; y < cam.height; y += threads)
      for (int x = 0; x < cam.width; x++) {
        SynthRng rng(mixKeys(mixKeys(settings.seed, viewKey), uint64_t(y) * uint64_t(cam.width) + x));
        glm::dvec3 sum(0.0);
        bool allMetWater = true;
        for (int sy = 0; sy < n; sy++)
          for (int sx = 0; sx < n; sx++) {
            double px = x + (sx + rng.uniform()) / n, py = y + (sy + rng.uniform()) / n;
            RayResult r = shadeCameraRay(scene, water, ior, eye, cameraRayDirection(cam, px, py));
            sum += r.colour;
            if (!r.metWater) {
              allMetWater = false;
              part.missing++;
            }
            if (r.hitScene) {
              double depth = -(worldToCamera * glm::dvec4(r.scenePoint, 1.0)).z;
              part.nearDepth = std::min(part.nearDepth, depth);
              part.farDepth = std::max(part.farDepth, depth);
            }
          }
        sum /= double(n * n);
        size_t i = size_t(y) * cam.width + x;
        for (int c = 0; c < 3; c++) out.rgb[i * 3 + c] = float(std::clamp(sum[c], 0.0, 1.0));
        out.mask[i] = allMetWater ? 1.0f : 0.0f;
      }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; t++) pool.emplace_back(work, t);
  work(0);
  for (auto& th : pool) th.join();
  out.nearDepth = 1e300;
  out.farDepth = -1e300;
  for (const auto& p : partial) {
    out.nearDepth = std::min(out.nearDepth, p.nearDepth);
    out.farDepth = std::max(out.farDepth, p.farDepth);
    out.samplesMissingWater += p.missing;
  }
  if (out.farDepth < out.nearDepth) out.nearDepth = out.farDepth = 0;
  return out;
}

}  // namespace refrax::synth
