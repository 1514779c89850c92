// The sheet of the paper's Algorithm 2 (learners/mpc/): a row per MPC episode, runs grouped by
// their planner, and the memory of its buffers, ensemble, planner and classifier fit.
#include <algorithm>

#include "cmbrl/run/learner_family.h"
#include "cmbrl/run/progress_columns.h"

namespace cmbrl {
namespace {

RunMemory MpcMemory(const RunSizes& sizes) {
  constexpr double kFloat = 4.0;
  const double s = sizes.state_dim, a = sizes.action_dim;
  const TrainingLoopOptions& t = sizes.training;
  const EnsembleOptions& e = sizes.ensemble;
  const PlannerSettings& p = sizes.planning;
  RunMemory m;
  m.transitions = static_cast<double>(t.transition_capacity) * (2 * s + a) * kFloat;
  m.labeled_states = (static_cast<double>(t.safe_capacity) + t.unsafe_capacity) * s * kFloat;
  // Weights, gradients and Adam's two moments of every member, and one batch's activations.
  double widest = s;
  for (const int width : e.hidden_sizes) widest = std::max(widest, static_cast<double>(width));
  const double members = e.ensemble_size;
  m.ensemble =
      EnsembleParameterBytes(e, sizes.state_dim, sizes.action_dim) +
      members * static_cast<double>(e.batch_size) * widest * kFloat * (e.hidden_sizes.size() + 1);
  // The planner keeps every step's predicted states of the population (E, N, H, S) and the
  // widest layer's activations; random shooting scores its samples the same way.
  const double samples = std::max<double>(p.cross_entropy.population, p.random.samples);
  const double horizon = p.problem.horizon;
  m.planning = members * samples * (horizon * (s + a) + 2 * widest) * kFloat;
  // The classifier's training matrix: every unsafe state and up to safe_per_unsafe times as
  // many safe ones, in XGBoost's copy too.
  m.classifier_fit =
      2.0 *
      std::min<double>(t.safe_capacity + t.unsafe_capacity,
                       (sizes.classifier.safe_per_unsafe + 1.0) * t.unsafe_capacity) *
      s * kFloat;
  return m;
}

}  // namespace

const FamilySheet& MpcFamily() {
  static const FamilySheet sheet = {
      "MPC",
      ProgressLog::kEpisodes,
      {"Epoch", "Episode", kEpRetColumn, kEpCostColumn, kTotalEnvInteractsColumn,
       "PretrainInteracts", kTimeColumn, "DynamicsValMSE", "ClassifierSafeAcc",
       "ClassifierUnsafeAcc", kFeasibleFractionColumn, "MsPerPlan", kStepsColumn, "GoalsMet",
       // Added after the columns above: a run begun without them keeps its columns on resume.
       kHazardStepsColumn, kVaseStepsColumn,
       // EpRawCost before it, for a Python environment's run.
       kCpuTimeColumn},
      MethodAxis::kPlanner,
      {"ensemble", "classifier", "planning", "objective", "reward_model", "termination_model"},
      MpcMemory,
  };
  return sheet;
}

}  // namespace cmbrl
