// Tool offset change: the ball moves on the flange from some cycle on (a step; the cycle searched
// on the training rows of every fold).
#include <algorithm>
#include <cmath>

#include "../robot_fit_kit.h"
#include "ramtk/kinematics/forward.h"

namespace ramtk::diagnose::robot_detail {
namespace {

// The base design plus the ball's shift from cycle `from` on.
Design StepDesign(const Context& ctx, int from) {
  std::vector<Mat3X> c;
  for (const Row& r : ctx.rows->rows) c.push_back(r.cycle_pos >= from ? Mat3X(r.ball_dir) : Mat3X(Mat3X::Zero(3, 3)));
  Design d = ctx.base;
  AddStaticColumns(c, {"dx_mm", "dy_mm", "dz_mm"}, &d);
  return d;
}

// The step cycle on `grid` that fits the training rows best, and its fit.
int BestStep(const Context& ctx, const std::vector<int>& grid, const std::vector<char>& train, Fit* fit) {
  const std::vector<Row>& rows = ctx.rows->rows;
  const int n = static_cast<int>(rows.size()), num_cycles = ctx.rows->num_cycles;
  double best = INFINITY;
  int best_c = grid[0];
  *fit = SolveDesign(rows, StepDesign(ctx, grid[0]), train, num_cycles);  // defined even if no step is finite
  for (int c : grid) {
    const Design d = StepDesign(ctx, c);
    const Fit f = SolveDesign(rows, d, train, num_cycles);
    double ss = 0;
    for (int i = 0; i < n; ++i)
      if (train[i]) ss += FitResidual(rows, d, f, i).squaredNorm();
    if (ss < best) best = ss, best_c = c, *fit = f;
  }
  return best_c;
}

void FitToolOffsetChange(const Context& ctx, CauseOutput out) {
  const std::vector<Row>& rows = ctx.rows->rows;
  const int num_cycles = ctx.rows->num_cycles;
  const int n = static_cast<int>(rows.size());
  std::vector<int> grid;
  const int stride = std::max(1, (num_cycles - 1) / 30);
  for (int c = 1; c < num_cycles; c += stride) grid.push_back(c);
  Evaluated e;
  e.cv.heldout_residual.assign(n, Eigen::Vector3d::Zero());
  for (int k = 0; k < ctx.folds; ++k) {
    std::vector<char> train(n);
    for (int i = 0; i < n; ++i) train[i] = ctx.fold_of_row[i] != k;
    Fit f;
    const int c = BestStep(ctx, grid, train, &f);
    const Design d = StepDesign(ctx, c);
    for (int i = 0; i < n; ++i) {
      if (train[i]) continue;
      const Eigen::Vector3d r = FitResidual(rows, d, f, i);
      e.cv.heldout_residual[i] = r;
      e.cv.heldout_ss += r.squaredNorm();
      e.cv.heldout_n += 3;
    }
  }
  Fit full;
  const int from = BestStep(ctx, grid, std::vector<char>(n, 1), &full);
  e.design = StepDesign(ctx, from);
  e.cv.full = full;
  for (int i = 0; i < n; ++i) e.cv.train_ss += FitResidual(rows, e.design, full, i).squaredNorm(), e.cv.train_n += 3;
  e.fit = MakeFit("tool_offset_change", 4, e.cv);
  ReportStatic(e.design, e.cv, ctx.base.ns, ctx.sigma, {{"dx_mm", 1.0}, {"dy_mm", 1.0}, {"dz_mm", 1.0}}, &e.fit);
  e.fit.parameters["from_cycle"] = ctx.rows->cycle_numbers[from];
  out.evaluated->push_back(std::move(e));
}

// The ball moves on the flange from a cycle in the middle half on.
void PlantToolOffsetChange(PlantContext* p) {
  const Eigen::Vector3d shift = p->random.Unit() * p->random.Uniform(0.05, 0.3);
  const int from = p->options->cycles / 4 + p->random.Pick(p->options->cycles / 2);
  p->draw->truth["shift_mm"] = shift.norm();
  p->draw->truth["from_cycle"] = from;
  p->draw->description = "ball moves " + Fmt(shift.norm()) + " mm on the flange at cycle " + std::to_string(from);
  const Isometry3& sensor_from_base = p->result->setup.sensor_from_base;
  for (auto& m : p->result->ball.rows)
    if (m.cycle >= from)
      m.position_mm += sensor_from_base.linear() * kinematics::BaseFromFlange(*p->model, m.q_controller).linear() * shift;
}

}  // namespace

const RobotCauseCode kToolOffsetChange{3, "", true, FitToolOffsetChange, nullptr, PlantToolOffsetChange};

}  // namespace ramtk::diagnose::robot_detail
