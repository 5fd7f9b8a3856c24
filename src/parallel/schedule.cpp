#include "parallel/schedule.h"

#include <algorithm>
#include <cstdlib>

#include "core/error.h"

namespace pvrt {

WorkPlan makeWorkPlan(const ScheduleSettings& s, int width, int height, int workers) {
  WorkPlan plan;
  plan.strategy = s.strategy;
  plan.chunk = s.chunk;
  workers = std::max(1, workers);
  const int g = std::max(1, s.granule);
  const long bands = (long(height) + g - 1) / g;  // rows when g = 1
  auto band = [&](long b0, long b1) { return WorkItem{0, int(b0 * g), width, int(std::min(long(height), b1 * g))}; };
  switch (s.strategy) {
    case Strategy::Block:
      for (int w = 0; w < workers; ++w) {
        const long b0 = bands * w / workers, b1 = bands * (w + 1) / workers;
        if (b1 > b0) {
          plan.items.push_back(band(b0, b1));
          plan.owner.push_back(w);
        }
      }
      break;
    case Strategy::Cyclic:
      for (long b = 0; b < bands; ++b) {
        plan.items.push_back(band(b, b + 1));
        plan.owner.push_back(int(b % workers));
      }
      break;
    case Strategy::Tiles: {
      const int t = (std::max(1, s.tileSize) + g - 1) / g * g;
      for (int y = 0; y < height; y += t)
        for (int x = 0; x < width; x += t)
          plan.items.push_back({x, y, std::min(width, x + t), std::min(height, y + t)});
      break;
    }
    default:  // OpenMP row schedules
      for (long b = 0; b < bands; ++b) plan.items.push_back(band(b, b + 1));
      break;
  }
  return plan;
}

Strategy parseStrategy(const std::string& name) {
  static const std::pair<const char*, Strategy> names[] = {
      {"block", Strategy::Block},     {"cyclic", Strategy::Cyclic}, {"static", Strategy::Static},
      {"dynamic", Strategy::Dynamic}, {"guided", Strategy::Guided}, {"runtime", Strategy::Runtime},
      {"tiles", Strategy::Tiles}};
  for (const auto& [n, s] : names)
    if (name == n) return s;
  throw Error(ExitCode::Usage, "unknown schedule \"" + name +
                                   "\" (use block, cyclic, static, dynamic, guided, runtime or tiles)");
}

const char* strategyName(Strategy s) {
  switch (s) {
    case Strategy::Block: return "block";
    case Strategy::Cyclic: return "cyclic";
    case Strategy::Static: return "static";
    case Strategy::Dynamic: return "dynamic";
    case Strategy::Guided: return "guided";
    case Strategy::Runtime: return "runtime";
    case Strategy::Tiles: return "tiles";
  }
  return "?";
}

bool scheduleFromEnvironment(ScheduleSettings& s) {
  const char* env = std::getenv("OMP_SCHEDULE");
  if (!env || !*env) return false;
  std::string v(env);
  if (v.rfind("monotonic:", 0) == 0) v = v.substr(10);
  if (v.rfind("nonmonotonic:", 0) == 0) v = v.substr(13);
  const auto comma = v.find(',');
  const std::string kind = v.substr(0, comma);
  Strategy st;
  if (kind == "static") st = Strategy::Static;
  else if (kind == "dynamic") st = Strategy::Dynamic;
  else if (kind == "guided") st = Strategy::Guided;
  else return false;
  int chunk = 0;
  if (comma != std::string::npos) {
    char* end = nullptr;
    const long c = std::strtol(v.c_str() + comma + 1, &end, 10);
    if (*end != '\0' || c < 1 || c > 1 << 20) return false;
    chunk = int(c);
  }
  s.strategy = st;
  s.chunk = chunk;
  return true;
}

}  // namespace pvrt
