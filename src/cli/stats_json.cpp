#include "cli/stats_json.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "cli/light_buffer_totals.h"
#include "render/effects.h"

namespace pvrt::cli {

namespace {

using nlohmann::ordered_json;  // keys in the order written, as --stats prints them

ordered_json counts(const RenderStats& t) {
  return {{"primary_rays", t.primaryRays},
          {"vista_rays", t.vistaRays},
          {"shadow_rays", t.shadowRays},
          {"reflected_rays", t.reflectedRays},
          {"refracted_rays", t.refractedRays},
          {"transmitted_rays", t.transmittedRays},
          {"total_rays", t.totalRays()},
          {"intersection_tests", t.intersectionTests},
          {"shading_operations", t.shadingOps},
          {"non_finite_samples", t.nonFiniteSamples},
          {"non_finite_pixels", t.nonFinitePixels},
          {"work", t.work()}};
}

ordered_json threads(const std::vector<WorkerStats>& workers, bool withCounts) {
  ordered_json list = ordered_json::array();
  for (const WorkerStats& w : workers) {
    ordered_json t = {{"pixels", w.pixels}, {"seconds", w.seconds}};
    if (withCounts) {
      t["rays"] = w.counts.totalRays();
      t["work"] = w.counts.work();
    } else {
      t["work"] = w.counts.intersectionTests;  // an MPI rank's threads send their total work only
    }
    list.push_back(std::move(t));
  }
  return list;
}

// max / mean over the ranks that rendered (a dynamic master that only answers is left out).
ordered_json imbalance(const std::vector<RankStats>& ranks) {
  double maxW = 0, sumW = 0, maxC = 0, sumC = 0, active = 0;
  for (const RankStats& k : ranks) {
    maxW = std::max(maxW, double(k.counts.work()));
    sumW += double(k.counts.work());
    maxC = std::max(maxC, k.computeSeconds);
    sumC += k.computeSeconds;
    active += k.pixels > 0 ? 1 : 0;
  }
  return {{"work", sumW > 0 ? maxW / (sumW / active) : 0.0},
          {"compute_seconds", sumC > 0 ? maxC / (sumC / active) : 0.0},
          {"rendering_ranks", active}};
}

}  // namespace

std::string statsJson(const RunFigures& run, const RenderSettings& s, const Scene& scene, const RenderResult& r,
                      const std::vector<RankStats>& ranks) {
  ordered_json j;
  j["format"] = "pvrt-stats 1";
  j["scene"] = run.scene;
  j["output"] = run.output;
  ordered_json image = {{"width", s.width},
                        {"height", s.height},
                        {"rays_per_pixel", PixelSampler(s.sampler).count()},
                        {"sampler", samplerName(s.sampler.kind)},
                        {"spp", s.sampler.samplesPerPixel}};
  // Counted from 0, the end excluded: columns [x0, x1), rows [y0, y1).
  if (s.region)
    image["region"] = {{"x0", s.region->x0}, {"y0", s.region->y0}, {"x1", s.region->x1}, {"y1", s.region->y1}};
  j["image"] = std::move(image);
  ordered_json backend = {{"name", run.backend}, {"schedule", strategyName(s.schedule.strategy)}};
  if (ranks.empty()) {
    backend["workers"] = r.workers.size();
  } else {
    backend["ranks"] = ranks.size();
    backend["gather"] = run.gather;
  }
  j["backend"] = std::move(backend);
  j["kernel_effects"] = effectNames(r.effects);
  j["objects"] = {{"primitives", scene.bvh.size()}, {"lights", scene.lights.size()}};
  j["counts"] = counts(r.totals);
  j["length_unit"] = {{"unit", scene.tol.unit}, {"typical_object_size", scene.tol.typicalSize}};
  const BvhStats& b = scene.bvh.stats();
  j["bvh"] = {{"nodes", b.nodes},
              {"leaves", b.leaves},
              {"depth", b.maxDepth},
              {"bytes", b.bytes},
              {"build_seconds", b.buildSeconds}};
  const auto [buffers, entries, bytes, cells] = lightBufferTotals(scene);
  j["light_buffers"] = {{"count", buffers},
                        {"max_cells_per_side", cells},
                        {"entries", entries},
                        {"bytes", bytes},
                        {"build_seconds", scene.lightBufferSeconds}};
  j["memory_limit"] = {{"bytes", scene.memoryLimit}, {"lights_without_buffer", scene.lightsOverMemoryLimit}};
  j["seconds"] = {
      {"load", run.load.wall}, {"build", run.build.wall}, {"render", r.seconds}, {"write", run.write.wall}};
  j["cpu_seconds"] = {
      {"load", run.load.cpu}, {"build", run.build.cpu}, {"render", run.render.cpu}, {"write", run.write.cpu}};
  j["rays_per_second"] = r.seconds > 0 ? double(r.totals.totalRays()) / r.seconds : 0.0;
  j["peak_memory_bytes"] = {
      {"run", run.peakBytes}, {"after_load", run.loadPeakBytes}, {"after_build", run.buildPeakBytes}};
  if (ranks.empty()) {
    j["workers"] = threads(r.workers, true);
  } else {
    ordered_json list = ordered_json::array();
    for (const RankStats& k : ranks)
      list.push_back({{"items", k.items},
                      {"pixels", k.pixels},
                      {"work", k.counts.work()},
                      {"compute_seconds", k.computeSeconds},
                      {"comm_seconds", k.commSeconds},
                      {"idle_seconds", k.idleSeconds},
                      {"wall_seconds", k.wallSeconds},
                      {"bytes_sent", k.bytesSent},
                      {"threads", threads(k.threads, false)}});
    j["ranks"] = std::move(list);
    j["imbalance"] = imbalance(ranks);
  }
  if (run.budget) {
    const BudgetPlan& p = *run.budget;
    ordered_json pilots = ordered_json::array();
    for (size_t i = 0; i < p.pilotSamples.size(); ++i)
      pilots.push_back({{"spp", p.pilotSamples[i]},
                        {"rays_per_pixel", p.points[i].rays},
                        {"seconds_per_pixel", p.points[i].secondsPerPixel}});
    j["time_budget"] = {{"method", "pilots"},
                        {"budget_seconds", run.timeBudget},
                        {"chosen_spp", p.samplesPerPixel},
                        {"predicted_render_seconds", p.predictedSeconds},
                        {"pilot_seconds", p.pilotSeconds},
                        {"pilot_share", p.pilotShare},
                        {"fits", p.fits},
                        {"pilots", std::move(pilots)}};
  }
  if (!r.passes.empty()) {
    ordered_json passes = ordered_json::array();
    for (const PassRecord& p : r.passes)
      passes.push_back({{"first_sample", p.first}, {"end_sample", p.last}, {"seconds", p.seconds}});
    j["time_budget"] = {{"method", "passes"},
                        {"budget_seconds", run.timeBudget},
                        {"chosen_spp", r.passes.back().last},
                        {"passes", std::move(passes)}};
  }
  // A file name need not be UTF-8: its bytes are replaced rather than refused.
  return j.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace pvrt::cli
