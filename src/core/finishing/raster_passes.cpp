// Raster passes over the shallow part of the region: rows along x, runs where the row crosses the region, points on
// the CL surface refined to the chordal tolerance, cut only where the body clears.
#include <algorithm>
#include <cmath>

#include "surface_passes.h"

namespace art2part::surface {

namespace {

// The runs of one row y: stretches of consecutive raster nodes in the nearest node row, sampled, refined, split where
// the body cannot clear.
std::vector<Pass> rasterRow(const Context& ctx, double y) {
  const Grid& g = ctx.grid;
  const int j = g.nearestJ(y);
  std::vector<Pass> runs;
  int i = 0;
  while (i < g.nx) {
    if (!ctx.raster[g.node(i, j)]) {
      ++i;
      continue;
    }
    int end = i;
    while (end + 1 < g.nx && ctx.raster[g.node(end + 1, j)]) ++end;
    // The stretch of x whose nearest node is one of i..end.
    const double xa = g.x(i) - (i > 0 ? 0.5 * g.pitch : 0), xb = g.x(end) + (end + 1 < g.nx ? 0.5 * g.pitch : 0);
    const int n = std::max(1, static_cast<int>(std::ceil((xb - xa) / ctx.sample_step)));
    std::vector<Vec3> samples;
    samples.reserve(n + 1);
    for (int k = 0; k <= n; ++k) {
      // Just inside the stretch's ends, so their nearest node is the stretch's.
      const double x = k == 0 ? xa + 1e-9 : (k == n ? xb - 1e-9 : xa + (xb - xa) * k / n);
      samples.emplace_back(x, y, ctx.drop(x, y));
    }
    // Split where the body cannot clear; refine the stretches that remain.
    Pass run;
    auto close = [&] {
      if (run.points.size() >= 2) runs.push_back(Pass{thin(run.points, ctx.gouge_tolerance, ctx.leave_tolerance, false), false});
      run.points.clear();
    };
    for (std::size_t k = 0; k < samples.size(); ++k) {
      if (!ctx.bodyClear(samples[k])) {
        close();
        continue;
      }
      if (!run.points.empty()) {
        std::vector<Vec3> between;
        refineInterval(ctx, run.points.back(), samples[k], between);
        bool clear = true;
        for (const Vec3& p : between) clear = clear && ctx.bodyClear(p);
        if (!clear) {
          close();
        } else {
          run.points.insert(run.points.end(), between.begin(), between.end());
        }
      }
      run.points.push_back(samples[k]);
    }
    close();
    i = end + 1;
  }
  return runs;
}

}  // namespace

std::vector<std::vector<Pass>> rasterRows(const Context& ctx, double& mean_step) {
  const Grid& g = ctx.grid;
  std::vector<double> row_min(g.ny, kInf);  // the least spacing any raster node of a node row asks for
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (ctx.raster[g.node(i, j)]) row_min[j] = std::min(row_min[j], ctx.row_spacing[g.node(i, j)]);
  std::vector<double> ys;
  double spanned = 0;  // y covered by rows within stretches, for the mean spacing
  int gaps = 0;
  const double half = 0.5 * g.pitch;
  for (int j = 0; j < g.ny;) {
    if (std::isinf(row_min[j])) {
      ++j;
      continue;
    }
    // A stretch of node rows with raster nodes: rows from its lower edge to its upper edge, each spaced by the least
    // spacing of the node rows it spans to the next.
    int end = j;
    while (end + 1 < g.ny && !std::isinf(row_min[end + 1])) ++end;
    const double ya = g.y(j) - (j > 0 ? half : 0) + 1e-9, yb = g.y(end) + (end + 1 < g.ny ? half : 0) - 1e-9;
    double y = ya;
    while (true) {
      ys.push_back(y);
      if (y >= yb) break;
      double step = kInf;
      for (int k = g.nearestJ(y); k <= end && g.y(k) - half <= y + step; ++k) step = std::min(step, row_min[k]);
      const double next = std::min(yb, y + step);
      spanned += next - y;
      ++gaps;
      y = next;
    }
    j = end + 1;
  }
  mean_step = gaps > 0 ? spanned / gaps : 0;
  std::vector<std::vector<Pass>> out(ys.size());
  parallelFor(static_cast<int>(ys.size()), ctx.threads, [&](int k) { out[k] = rasterRow(ctx, ys[k]); });
  return out;
}

}  // namespace art2part::surface
