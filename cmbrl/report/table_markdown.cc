#include "cmbrl/report/table_markdown.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "cmbrl/report/run_logs.h"
#include "cmbrl/report/statistics.h"

namespace cmbrl {
namespace {

// Per-seed counts for people: whole numbers as such, interpolated ones (model-free epoch logs)
// to one decimal.
std::string Counts(const std::vector<double>& values) {
  std::vector<std::string> texts;
  for (const double v : values) {
    texts.push_back(v == std::round(v) ? fmt::format("{:.0f}", v) : fmt::format("{:.1f}", v));
  }
  return fmt::format("{}", fmt::join(texts, ", "));
}

// A figure with `digits` decimals, or "-" where there is none (NaN).
std::string Figure(double value, int digits) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, digits) : "-";
}

// Counts joined by ", ", or "-" where there are none.
std::string CountsOrDash(const std::vector<int>& counts) {
  return counts.empty() ? "-" : fmt::format("{}", fmt::join(counts, ", "));
}

// A cell's row label: its task, with its setting where it has one.
std::string RowLabel(const TableCell& cell) { return WithSetting(cell.task, cell.setting); }

// The first epochs' violations and mean returns, each as "mean (per seed)", or "-" for none.
struct FirstEpochTexts {
  std::string violations, returns;
};
FirstEpochTexts DescribeFirstEpochs(const std::vector<FirstEpoch>& epochs) {
  if (epochs.empty()) return {"-", "-"};
  std::vector<double> violations, returns;
  std::vector<std::string> return_texts;
  for (const FirstEpoch& epoch : epochs) {
    violations.push_back(epoch.violations);
    returns.push_back(epoch.mean_return);
    return_texts.push_back(fmt::format("{:.1f}", epoch.mean_return));
  }
  return {fmt::format("{:.1f} ({})", Mean(violations), Counts(violations)),
          fmt::format("{:.1f} ({})", Mean(returns), fmt::join(return_texts, ", "))};
}

// The cell of a task, planner and setting, or nullptr when the table has none.
const TableCell* FindCell(const std::vector<TableCell>& cells, const std::string& task,
                          const std::string& planner, const std::string& setting) {
  const auto it = std::find_if(cells.begin(), cells.end(), [&](const TableCell& c) {
    return c.task == task && c.planner == planner && c.setting == setting;
  });
  return it == cells.end() ? nullptr : &*it;
}

// The table's rows: its distinct (task, setting) pairs, in the cells' order.
std::vector<std::pair<std::string, std::string>> TaskSettingRows(
    const std::vector<TableCell>& cells) {
  std::vector<std::pair<std::string, std::string>> rows;
  for (const TableCell& cell : cells) {
    const std::pair<std::string, std::string> row(cell.task, cell.setting);
    if (std::find(rows.begin(), rows.end(), row) == rows.end()) rows.push_back(row);
  }
  return rows;
}

// The distinct values of one field of the cells (task or planner), in the table's order.
std::vector<std::string> DistinctInOrder(const std::vector<TableCell>& cells,
                                         std::string TableCell::*field) {
  std::vector<std::string> values;
  for (const TableCell& cell : cells) {
    if (std::find(values.begin(), values.end(), cell.*field) == values.end()) {
      values.push_back(cell.*field);
    }
  }
  return values;
}

// TableMarkdown's sections after Table I and the returns.

// Each cell against the original's seeds over the same window ("" without them).
std::string OriginalComparisonMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  if (std::none_of(cells.begin(), cells.end(),
                   [](const TableCell& c) { return !c.original_per_seed.empty(); })) {
    return "";
  }
  std::string text = fmt::format(
      "\nAgainst the original's own logs over the same {} steps (its seeds 0, 10 and 100; "
      "data/reference/): where our mean lies against its seeds' range; whether it reproduces "
      "the original, that is lies within that range widened by 30% (0.7 x its lowest seed to "
      "1.3 x its highest; for MPC-RCE, the paper's method, only the upper end counts); the "
      "return of the last 10 episodes, and whether it reproduces the original's by the same "
      "widened range, both ends for every method.\n\n"
      "| task | method | ours (per seed) | original (per seed) | ours vs its range | "
      "reproduces | return, ours | return, original | return reproduces | episodes with >= 20, "
      "ours | the original's | feasible fraction, ours |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
      window);
  for (const TableCell& cell : cells) {
    if (cell.original_per_seed.empty()) continue;
    text += fmt::format(
        "| {} | {} | {:.1f} ({}) | {:.1f} ({}) | {} | {} | {} | {} | {} | {} | {} | {} |\n",
        RowLabel(cell), MethodLabel(cell.planner), cell.mean, Counts(cell.per_seed),
        Mean(cell.original_per_seed), Counts(cell.original_per_seed), VersusOriginal(cell),
        WithinWidenedRange(cell), Figure(cell.return_mean, 2),
        Figure(Mean(cell.original_final_returns), 2), ReturnWithinWidenedRange(cell),
        CountsOrDash(cell.heavy_episodes), CountsOrDash(cell.original_heavy_episodes),
        Figure(Mean(cell.feasible_fractions), 3));
  }
  return text;
}

// The first epochs, ours against the original's ("" where no cell has both).
std::string FirstEpochMarkdown(const std::vector<TableCell>& cells) {
  const bool any_first_epoch = std::any_of(cells.begin(), cells.end(), [](const TableCell& c) {
    return !c.first_epochs.empty() && !c.original_first_epochs.empty();
  });
  if (!any_first_epoch) return "";
  std::string text =
      "\nThe first epoch, the one comparison on equal data: each run's first episodes before "
      "its first refit (10 in the paper's loop), planned with models fitted on the random "
      "pre-training data only, as the original's first 10 were. Their violations (sum) and "
      "return (mean of the episodes), mean over seeds (per seed).\n\n"
      "| task | method | episodes, ours | violations, ours | the original's | return, ours | "
      "the original's |\n|---|---|---|---|---|---|---|\n";
  for (const TableCell& cell : cells) {
    if (cell.first_epochs.empty() || cell.original_first_epochs.empty()) continue;
    std::vector<int> counts;
    for (const FirstEpoch& epoch : cell.first_epochs) {
      if (std::find(counts.begin(), counts.end(), epoch.episodes) == counts.end()) {
        counts.push_back(epoch.episodes);
      }
    }
    const FirstEpochTexts ours = DescribeFirstEpochs(cell.first_epochs);
    const FirstEpochTexts original = DescribeFirstEpochs(cell.original_first_epochs);
    text += fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", RowLabel(cell),
                        MethodLabel(cell.planner), fmt::join(counts, ", "), ours.violations,
                        original.violations, ours.returns, original.returns);
  }
  return text;
}

// Where the violations happened, for the cells whose runs logged it ("" where none did).
std::string ViolationCausesMarkdown(const std::vector<TableCell>& cells) {
  if (std::all_of(cells.begin(), cells.end(),
                  [](const TableCell& c) { return c.hazard_steps.empty(); })) {
    return "";
  }
  std::string text =
      "\nWhere the violations happened (runs that log it: HazardSteps and VaseSteps): violating "
      "steps inside a hazard and at a vase (touched, or moving faster than allowed after a "
      "push), per seed. A step can be both.\n\n"
      "| task | method | violating steps | in hazards | at vases |\n|---|---|---|---|---|\n";
  for (const TableCell& cell : cells) {
    if (cell.hazard_steps.empty()) continue;
    text += fmt::format("| {} | {} | {} | {} | {} |\n", RowLabel(cell), MethodLabel(cell.planner),
                        Counts(cell.per_seed), CountsOrDash(cell.hazard_steps),
                        CountsOrDash(cell.vase_steps));
  }
  return text;
}

// What the cells count in: agent steps and episodes (MPC runs), environment steps and epochs
// (model-free runs), or both named where a table holds both.
struct CountUnits {
  std::string steps, violations, returns;
};
CountUnits UnitsOf(const std::vector<TableCell>& cells) {
  const FamiliesPresent families = FamiliesIn(cells);
  const CountUnits mpc{"agent steps", "the EpCost of the episodes that ended in the window",
                       "the mean EpRet of each run's last 10 episodes in it"};
  const CountUnits model_free{"environment steps",
                              "the cumulative cost at the window's end, interpolated in its epoch",
                              "the mean AverageEpRet of each run's last 10 epochs in it "
                              "in which an episode ended"};
  if (!families.model_free) return mpc;
  if (!families.mpc) return model_free;
  return {"steps (agent steps for MPC runs, environment steps for model-free ones)",
          mpc.violations + "; for model-free runs " + model_free.violations,
          mpc.returns + "; for model-free runs " + model_free.returns};
}

// "12.3 [8.0, 17.1]": a mean and its bootstrap 90% interval.
std::string MeanWithInterval(const std::vector<double>& values, int digits) {
  if (values.empty()) return "-";
  const MeanInterval interval = BootstrapMeanInterval(values);
  return fmt::format("{} [{}, {}]", Figure(Mean(values), digits), Figure(interval.low, digits),
                     Figure(interval.high, digits));
}

std::string PerSeed(const std::vector<double>& values, int digits) {
  std::vector<std::string> texts;
  for (const double v : values) texts.push_back(Figure(v, digits));
  return texts.empty() ? "-" : fmt::format("{}", fmt::join(texts, ", "));
}

// One cell against the original: its seeds over the same window when its logs cover it, else
// Table I when the window is the paper's; nothing otherwise.
std::optional<std::string> OriginalComparison(const TableCell& cell, std::int64_t window) {
  const std::string label = fmt::format("{} {}", RowLabel(cell), MethodLabel(cell.planner));
  if (!cell.original_per_seed.empty()) {
    const std::string verdict = VersusOriginal(cell);
    return fmt::format(
        "{}: {:.1f} in the first {} steps, the original {:.1f} ({}); ours is {} its seeds' "
        "range{}.",
        label, cell.mean, window, Mean(cell.original_per_seed), Counts(cell.original_per_seed),
        verdict,
        verdict == "inside"  ? ""
        : verdict == "above" ? ": more violations than the original"
                             : ": fewer violations than the original");
  }
  if (cell.paper && window == kPaperWindow) {
    return fmt::format("{}: {:.1f} against the paper's {:.0f} ({:.2f}x).", label, cell.mean,
                       *cell.paper, *cell.paper > 0 ? cell.mean / *cell.paper : 0.0);
  }
  return std::nullopt;
}

// Per task: whether the paper's method (MPC-RCE) violated less than each other planner, and
// whether its final return is comparable to the best other's.
void PapersMethodAgainstOthers(const std::string& task,
                               const std::map<std::string, const TableCell*>& row,
                               const TableCell& method, std::vector<std::string>& notes) {
  const std::string name = MethodLabel(method.planner);
  std::vector<std::string> worse, not_worse;
  for (const auto& [planner, cell] : row) {
    if (cell == &method) continue;
    (cell->mean > method.mean ? worse : not_worse).push_back(MethodLabel(planner));
  }
  if (!worse.empty() || !not_worse.empty()) {
    notes.push_back(fmt::format(
        "{}: {} {:.1f} violations on average; {}{}{}.", task, name, method.mean,
        worse.empty() ? "" : fmt::format("more for {}", fmt::join(worse, " and ")),
        !worse.empty() && !not_worse.empty() ? "; " : "",
        not_worse.empty() ? ""
                          : fmt::format("NOT more for {} (the paper's claim fails here)",
                                        fmt::join(not_worse, " and "))));
  }
  double best_other = -std::numeric_limits<double>::infinity();
  std::string best_label;
  for (const auto& [planner, cell] : row) {
    if (cell != &method && cell->return_mean > best_other) {
      best_other = cell->return_mean;
      best_label = MethodLabel(planner);
    }
  }
  if (!best_label.empty()) {
    notes.push_back(
        fmt::format("{}: {}'s final return {:.2f} against {:.2f} for {}, the best of the others{}.",
                    task, name, method.return_mean, best_other, best_label,
                    method.return_mean >= 0.8 * best_other || best_other <= 0
                        ? ""
                        : " (less than 80% of it: not comparable reward)"));
  }
}

}  // namespace

std::string TableMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  const std::vector<std::string> planners = DistinctInOrder(cells, &TableCell::planner);
  const CountUnits units = UnitsOf(cells);
  const bool any_paper =
      std::any_of(cells.begin(), cells.end(), [](const TableCell& c) { return c.paper; });
  std::string text = fmt::format(
      "Violations during the first {} {}: ours as mean ± std over seeds (seeds){}. * marks a "
      "cell whose shortest run stopped before the window's end.\n\n| task |",
      window, units.steps,
      any_paper ? ", the paper's Table I (mean of 3 seeds over 10,000 steps) in brackets" : "");
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " |";
  text += "\n|---|";
  for (size_t i = 0; i < planners.size(); ++i) text += "---|";
  text += "\n";
  const std::vector<std::pair<std::string, std::string>> rows = TaskSettingRows(cells);
  for (size_t r = 0; r < rows.size(); ++r) {
    const auto& [task, setting] = rows[r];
    if (r > 0) text += "\n";
    text += "| " + WithSetting(task, setting) + " |";
    for (const std::string& planner : planners) {
      const TableCell* it = FindCell(cells, task, planner, setting);
      if (it == nullptr) {
        text += " |";
        continue;
      }
      text += fmt::format(" {:.1f} ± {:.1f} ({}){}{}", it->mean, it->std, it->per_seed.size(),
                          it->fewest_steps < window ? "*" : "", it->source.empty() ? "" : "†");
      text += it->paper ? fmt::format(" [{:.0f}] |", *it->paper) : " |";
    }
  }
  std::vector<std::string> sources;
  for (const TableCell& cell : cells) {
    if (!cell.source.empty() &&
        std::find(sources.begin(), sources.end(), cell.source) == sources.end()) {
      sources.push_back(cell.source);
    }
  }
  if (!sources.empty()) {
    text += fmt::format(
        "\n\n† read from an earlier report's table ('{}'): its runs' logs are not kept, so the "
        "cell has no curve and no first epoch here.",
        fmt::join(sources, "', '"));
  }
  text += fmt::format(
      "\n\nReturn at the end of the same window: {}, mean ± std over seeds.\n\n| task |",
      units.returns);
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " |";
  text += "\n|---|";
  for (size_t i = 0; i < planners.size(); ++i) text += "---|";
  for (const auto& [task, setting] : rows) {
    text += "\n| " + WithSetting(task, setting) + " |";
    for (const std::string& planner : planners) {
      const TableCell* it = FindCell(cells, task, planner, setting);
      text += it == nullptr ? " |"
              : !std::isfinite(it->return_mean)
                  ? " - |"
                  : fmt::format(" {:.2f} ± {:.2f} |", it->return_mean, it->return_std);
    }
  }
  text += "\n";
  text += OriginalComparisonMarkdown(cells, window);
  text += FirstEpochMarkdown(cells);
  text += ViolationCausesMarkdown(cells);
  return text;
}

std::string ProtocolVerdictMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  const std::vector<std::string> planners = DistinctInOrder(cells, &TableCell::planner);
  const CountUnits units = UnitsOf(cells);
  std::string text = fmt::format(
      "Violations during the first {} {}: mean over seeds [bootstrap 90% interval of "
      "the mean]. \"Least\": the paper's method violates least, its interval wholly below every "
      "other method's (\"yes\"), or only its mean lowest (\"mean only\"). Against the "
      "original: where our mean lies against the range of the original's three seeds over the "
      "same window, for violations / for the return ({}).\n\n| task |",
      window, units.steps, units.returns);
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " |";
  text += " least? |";
  for (const std::string& planner : planners) text += " " + MethodLabel(planner) + " vs original |";
  text += "\n|---|";
  for (size_t i = 0; i < 2 * planners.size() + 1; ++i) text += "---|";
  text += "\n";
  for (const auto& [task, setting] : TaskSettingRows(cells)) {
    text += "| " + WithSetting(task, setting) + " |";
    std::optional<std::string> papers;
    for (const std::string& planner : planners) {
      const TableCell* cell = FindCell(cells, task, planner, setting);
      text += " " + (cell ? MeanWithInterval(cell->per_seed, 1) : std::string("-")) + " |";
      if (cell && IsPapersMethod(planner)) papers = planner;
    }
    std::string verdict = "-";
    if (papers) {
      const TableCell& ours = *FindCell(cells, task, *papers, setting);
      const MeanInterval ours_interval = BootstrapMeanInterval(ours.per_seed);
      bool lowest_mean = true, apart = true, others = false;
      for (const TableCell& other : cells) {
        if (other.task != task || other.setting != setting || other.planner == *papers) continue;
        others = true;
        lowest_mean = lowest_mean && ours.mean < other.mean;
        apart = apart && ours_interval.high < BootstrapMeanInterval(other.per_seed).low;
      }
      if (others) verdict = !lowest_mean ? "no" : apart ? "yes" : "mean only";
    }
    text += " " + verdict + " |";
    for (const std::string& planner : planners) {
      const TableCell* cell = FindCell(cells, task, planner, setting);
      if (cell == nullptr || cell->original_per_seed.empty()) {
        text += " - |";
        continue;
      }
      text += fmt::format(" {} / {} |", AgainstRange(cell->mean, cell->original_per_seed),
                          AgainstRange(cell->return_mean, cell->original_final_returns));
    }
    text += "\n";
  }
  return text;
}

std::string ProtocolCellsMarkdown(const std::vector<TableCell>& cells, std::int64_t window) {
  const CountUnits units = UnitsOf(cells);
  std::string text = fmt::format(
      "Every cell over the first {} {}: violations ({}) and return ({}), per seed in seed order, "
      "their mean [bootstrap 90% interval], and the original's seeds (0, 10, 100) from its "
      "logs. * marks a cell whose shortest run has not reached the window.\n\n"
      "| task | method | seeds | violations per seed | mean [90%] | original | vs original | "
      "return per seed | mean [90%] | original | vs original |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n",
      window, units.steps, units.violations, units.returns);
  for (const TableCell& cell : cells) {
    const std::string original = cell.original_per_seed.empty()
                                     ? "-"
                                     : fmt::format("{} ({})", PerSeed(cell.original_per_seed, 0),
                                                   Figure(Mean(cell.original_per_seed), 1));
    const std::string original_returns =
        cell.original_final_returns.empty()
            ? "-"
            : fmt::format("{} ({})", PerSeed(cell.original_final_returns, 2),
                          Figure(Mean(cell.original_final_returns), 2));
    const std::string vs = AgainstRange(cell.mean, cell.original_per_seed);
    const std::string vs_return = AgainstRange(cell.return_mean, cell.original_final_returns);
    text += fmt::format("| {} | {} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                        RowLabel(cell), MethodLabel(cell.planner), cell.per_seed.size(),
                        cell.fewest_steps < window ? "*" : "", Counts(cell.per_seed),
                        MeanWithInterval(cell.per_seed, 1), original, vs.empty() ? "-" : vs,
                        PerSeed(cell.final_returns, 2), MeanWithInterval(cell.final_returns, 2),
                        original_returns, vs_return.empty() ? "-" : vs_return);
  }
  return text;
}

namespace {

// The pairs of one (setting, against) over every task and method, in order of first sight.
struct PooledPairs {
  std::string setting, against;
  int cells = 0;
  std::vector<double> violations, returns, first_violations, first_returns;
};

PooledPairs& PoolOf(std::vector<PooledPairs>& pooled, const std::string& setting,
                    const std::string& against) {
  for (PooledPairs& p : pooled) {
    if (p.setting == setting && p.against == against) return p;
  }
  PooledPairs& p = pooled.emplace_back();
  p.setting = setting;
  p.against = against;
  return p;
}

std::string PValue(const std::vector<double>& differences) {
  return differences.empty() ? std::string("-")
                             : fmt::format("{:.3f}", PairedSignFlipP(differences));
}

// One row per setting against the first of its task and method, its pairs added to `pooled`.
std::string PairRows(const std::vector<TableCell>& cells, std::vector<PooledPairs>& pooled) {
  std::string text;
  for (const TableCell& first : cells) {
    // The first cell of its task and method in the table's order is the one compared against.
    const auto same_pair = [&](const TableCell& c) {
      return c.task == first.task && c.planner == first.planner;
    };
    if (&*std::find_if(cells.begin(), cells.end(), same_pair) != &first) continue;
    for (const TableCell& other : cells) {
      if (&other == &first || !same_pair(other)) continue;
      std::vector<std::uint64_t> seeds;
      std::vector<double> violations, returns;
      PooledPairs& pool = PoolOf(pooled, other.setting, first.setting);
      for (size_t i = 0; i < other.seeds.size(); ++i) {
        const auto it = std::find(first.seeds.begin(), first.seeds.end(), other.seeds[i]);
        if (it == first.seeds.end()) continue;
        const size_t j = static_cast<size_t>(it - first.seeds.begin());
        seeds.push_back(other.seeds[i]);
        violations.push_back(other.per_seed[i] - first.per_seed[j]);
        pool.first_violations.push_back(first.per_seed[j]);
        if (std::isfinite(other.final_returns[i]) && std::isfinite(first.final_returns[j])) {
          returns.push_back(other.final_returns[i] - first.final_returns[j]);
          pool.first_returns.push_back(first.final_returns[j]);
        }
      }
      pool.cells += seeds.empty() ? 0 : 1;
      pool.violations.insert(pool.violations.end(), violations.begin(), violations.end());
      pool.returns.insert(pool.returns.end(), returns.begin(), returns.end());
      text += fmt::format(
          "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", first.task,
          MethodLabel(first.planner), other.setting.empty() ? "-" : other.setting,
          first.setting.empty() ? "-" : first.setting,
          seeds.empty() ? std::string("none") : fmt::format("{}", fmt::join(seeds, ", ")),
          PerSeed(violations, 1), MeanWithInterval(violations, 1), PValue(violations),
          PerSeed(returns, 2), MeanWithInterval(returns, 2), PValue(returns));
    }
  }
  return text;
}

// An "all" row for each pair of settings compared in two or more cells.
std::string PooledRows(const std::vector<PooledPairs>& pooled) {
  std::string text;
  for (const PooledPairs& pool : pooled) {
    if (pool.cells < 2) continue;
    text += fmt::format(
        "| all | all | {} | {} | {} pairs in {} cells | (mean of {}: {}) | {} | {} | "
        "(mean of {}: {}) | {} | {} |\n",
        pool.setting.empty() ? "-" : pool.setting, pool.against.empty() ? "-" : pool.against,
        pool.violations.size(), pool.cells, pool.against, Figure(Mean(pool.first_violations), 1),
        MeanWithInterval(pool.violations, 1), PValue(pool.violations), pool.against,
        Figure(Mean(pool.first_returns), 2), MeanWithInterval(pool.returns, 2),
        PValue(pool.returns));
  }
  return text;
}

// The experiment's declared rule applied to every pair of settings over all their pairs.
std::string DecisionMarkdown(const DecisionRule& rule, const std::vector<PooledPairs>& pooled) {
  std::string text = fmt::format(
      "\n**Decision**, by the rule `experiment.yaml` declares ({}{}), over all the pairs of each "
      "setting and the one it is compared against:\n\n"
      "| setting | against | pairs | violations | return | decision |\n"
      "|---|---|---|---|---|---|\n",
      KindName(rule.kind),
      rule.kind == DecisionRule::Kind::kEquivalence
          ? fmt::format(": the 90% interval of the mean paired difference holds 0 and lies "
                        "within +-{:.0f}% of the first setting's mean",
                        100.0 * rule.band)
          : std::string(": the 90% interval of the mean paired difference wholly below or above "
                        "0"));
  for (const PooledPairs& pool : pooled) {
    if (pool.cells == 0) continue;
    const MeasureVerdict violations =
        DecideMeasure(rule, BootstrapMeanInterval(pool.violations), Mean(pool.first_violations));
    const MeasureVerdict returns =
        DecideMeasure(rule, BootstrapMeanInterval(pool.returns), Mean(pool.first_returns));
    text += fmt::format("| {} | {} | {} in {} cell{} | {} | {} | {} |\n",
                        pool.setting.empty() ? "-" : pool.setting,
                        pool.against.empty() ? "-" : pool.against, pool.violations.size(),
                        pool.cells, pool.cells == 1 ? "" : "s", violations.Text(), returns.Text(),
                        OverallVerdict(rule, violations, returns));
  }
  return text;
}

}  // namespace

std::string SettingComparisonMarkdown(const std::vector<TableCell>& cells,
                                      const std::optional<DecisionRule>& rule) {
  if (std::all_of(cells.begin(), cells.end(),
                  [](const TableCell& c) { return c.setting.empty(); })) {
    return "";
  }
  std::string text =
      "Each setting against the first of its task and method, paired by seed (the seeds both "
      "have): the per-seed differences (this setting's minus the first's) of violations and of "
      "the last-10-episode return, their mean [bootstrap 90% interval], and the two-sided "
      "p-value of an exact paired sign-flip test (with n pairs it cannot fall below 2/2^n). Where "
      "one pair of settings is compared in two or more cells, an \"all\" row pools their pairs "
      "(resampled alike), with the first setting's mean over those pairs beside it.\n\n"
      "| task | method | setting | against | seeds | violations: differences | mean [90%] | p | "
      "return: differences | mean [90%] | p |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<PooledPairs> pooled;
  text += PairRows(cells, pooled);
  text += PooledRows(pooled);
  if (!rule) return text;
  return text + DecisionMarkdown(*rule, pooled);
}

std::string RunCount(std::size_t runs) {
  return runs == 1 ? std::string("1 run") : fmt::format("{} runs", runs);
}

std::string ComputeMarkdown(const std::vector<TableCell>& cells) {
  // A column of CPU minutes where any cell's runs logged them (CpuTime).
  const bool cpu_column = std::any_of(cells.begin(), cells.end(), [](const TableCell& cell) {
    return !cell.run_minutes.empty() && !cell.run_cpu_minutes.empty();
  });
  std::string rows;
  double core_minutes = 0.0, longest = -1.0;
  double cpu_minutes = 0.0, cpu_runs_core_minutes = 0.0;
  bool one_core_a_run = true;
  std::string longest_run;
  int runs = 0, cpu_runs = 0;
  for (const TableCell& cell : cells) {
    if (cell.run_minutes.empty()) continue;
    const bool has_cpu = !cell.run_cpu_minutes.empty();
    for (size_t i = 0; i < cell.run_minutes.size(); ++i) {
      // A cell made by hand, or read before core-minutes were kept: one core a run.
      const double cores_minutes =
          i < cell.run_core_minutes.size() ? cell.run_core_minutes[i] : cell.run_minutes[i];
      core_minutes += cores_minutes;
      one_core_a_run = one_core_a_run && cores_minutes <= cell.run_minutes[i] * (1.0 + 1e-9);
      ++runs;
      if (has_cpu) {
        cpu_minutes += cell.run_cpu_minutes.at(i);
        cpu_runs_core_minutes += cores_minutes;
        ++cpu_runs;
      }
      if (cell.run_minutes[i] > longest) {
        longest = cell.run_minutes[i];
        longest_run = fmt::format("{} {}, seed {}", RowLabel(cell), MethodLabel(cell.planner),
                                  cell.seeds.at(i));
      }
    }
    rows +=
        fmt::format("| {} | {} | {} | {} | {} | {} |", RowLabel(cell), MethodLabel(cell.planner),
                    fmt::join(cell.seeds, ", "), PerSeed(cell.run_minutes, 0),
                    Figure(Median(cell.run_minutes), 0),
                    Figure(*std::max_element(cell.run_minutes.begin(), cell.run_minutes.end()), 0));
    if (cpu_column) rows += fmt::format(" {} |", has_cpu ? PerSeed(cell.run_cpu_minutes, 0) : "-");
    rows += "\n";
  }
  if (runs == 0) return "";
  const std::string cores =
      one_core_a_run ? "one core a run"
                     : "each session's time at the cores it ran on (sessions.jsonl's OpenBLAS "
                       "or LibTorch threads, whichever are more: a sweep sets them to the cores "
                       "it gives a run)";
  std::string cpu;
  if (cpu_column) {
    const char* whose = cpu_runs == 1 ? "its" : "their";
    cpu = fmt::format(
        " The CPU minutes are the processes' own (CpuTime at the last row: every thread's user "
        "and system time, over all sessions): {} used {:.1f} CPU-hours, {:.0f}% of {} "
        "core-hours; the rest is time {} cores stood idle or stopped, or (where the kernel "
        "accounts for it) the host gave to others.",
        cpu_runs < runs ? RunCount(static_cast<std::size_t>(cpu_runs))
        : runs == 1     ? std::string("the run")
                        : std::string("the runs"),
        cpu_minutes / 60.0,
        cpu_runs_core_minutes > 0 ? 100.0 * cpu_minutes / cpu_runs_core_minutes : 0.0, whose,
        whose);
  }
  return fmt::format(
      "Each run's wall time as made so far, in minutes: progress.csv's Time at its last row, "
      "over all its sessions (the work an interruption threw away is not counted), {}. {} took "
      "{:.1f} core-hours; the longest, {}, {:.0f} minutes.{}\n\n"
      "| task | method | seeds | minutes per seed | median | longest |{}\n"
      "|---|---|---|---|---|---|{}\n{}",
      cores, RunCount(static_cast<std::size_t>(runs)), core_minutes / 60.0, longest_run, longest,
      cpu, cpu_column ? " CPU minutes per seed |" : "", cpu_column ? "---|" : "", rows);
}

std::vector<std::string> OutcomeDifferences(const std::vector<TableCell>& cells,
                                            std::int64_t window) {
  std::vector<std::string> notes;
  // One row per task and setting: the paper's method is compared within its own setting.
  std::map<std::string, std::map<std::string, const TableCell*>> by_row;
  std::vector<std::string> rows;
  for (const TableCell& cell : cells) {
    const std::string row = RowLabel(cell);
    if (by_row.find(row) == by_row.end()) rows.push_back(row);
    by_row[row][cell.planner] = &cell;
  }
  for (const std::string& label : rows) {
    const auto& row = by_row[label];
    for (const auto& [planner, cell] : row) {
      if (IsPapersMethod(planner)) PapersMethodAgainstOthers(label, row, *cell, notes);
    }
    for (const TableCell& cell : cells) {  // the table's planner order
      if (RowLabel(cell) != label) continue;
      if (const auto note = OriginalComparison(cell, window)) notes.push_back(*note);
    }
  }
  return notes;
}

}  // namespace cmbrl
