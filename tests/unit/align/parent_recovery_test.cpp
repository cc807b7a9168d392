#include "surfcap/align/parent_recovery.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "surfcap/align/tree_alignment.hpp"

namespace surfcap::align {
namespace {

PairwiseResult result_with(double mean_residual, double uncovered = 0, double stacked = 0) {
  PairwiseResult result;
  result.mean_residual = mean_residual;
  result.uncovered_fraction = uncovered;
  result.stacked_fraction = stacked;
  return result;
}

TEST(PairwiseChecks, VerdictNamesTheWorstCheckAndSeparatesGrowthFromFailure) {
  const FailureOptions options;  // 4 mm, 1 % uncovered, 0.5 % stacked, growth 1.3
  EXPECT_EQ(verdict(result_with(0.002), 0.002, options), Verdict::pass);
  EXPECT_EQ(verdict(result_with(0.003), 0.002, options), Verdict::grown);
  EXPECT_EQ(verdict(result_with(0.003), 0.0, options), Verdict::pass);  // no reference residual
  EXPECT_EQ(verdict(result_with(0.005), 0.0, options), Verdict::failed);
  EXPECT_EQ(failure_reason(result_with(0.002, 0.05, 0.006), 0.0, options),
            "reconstruction not covered by the aligned template");  // 5× its limit against 1.2×
  EXPECT_EQ(failure_reason(result_with(0.003), 0.002, options), "mean residual grown beyond its parent's");
  FailureOptions no_growth = options;
  no_growth.residual_growth.reset();
  EXPECT_EQ(verdict(result_with(0.003), 0.002, no_growth), Verdict::pass);
}

TEST(ParentRecovery, CandidatesAreTheCheapestUsableFramesOrOneOfEachOtherSequence) {
  // Nodes 0–2 in sequence 0, 3–4 in sequence 1, 5 in sequence 2; child 2, tree parent 1.
  const std::vector<NodeFrame> nodes = {{0, 0}, {0, 1}, {0, 2}, {1, 0}, {1, 1}, {2, 0}};
  Eigen::MatrixXd costs = Eigen::MatrixXd::Zero(6, 6);
  costs.row(2) << 0.3, 0.1, 0.0, 0.2, 0.05, 0.4;
  const auto usable = [](long node) { return node != 2 && node != 0; };  // 0: not aligned yet
  EXPECT_EQ(candidate_parents(costs, 2, 1, nodes, usable, false), (std::vector<long>{4, 3, 5}));
  EXPECT_EQ(candidate_parents(costs, 2, 1, nodes, usable, true), (std::vector<long>{4, 5}));
}

TEST(ParentRecovery, EntryParentsAreOneFrameOfEachOtherSequenceThenTheRoot) {
  const std::vector<NodeFrame> nodes = {{0, 0}, {0, 1}, {0, 2}, {1, 0}, {1, 1}, {2, 0}};
  Eigen::MatrixXd costs = Eigen::MatrixXd::Zero(6, 6);
  costs.row(2) << 0.3, 0.1, 0.0, 0.2, 0.05, 0.4;
  const auto usable = [](long node) { return node != 2; };
  // Child 2, parent 1, root 0 (the parent's sequence: never a per-sequence candidate).
  EXPECT_EQ(entry_parents(costs, 2, 1, 0, nodes, usable, 2), (std::vector<long>{4, 5, 0}));
  EXPECT_EQ(entry_parents(costs, 2, 1, 0, nodes, usable, 1), (std::vector<long>{4, 0}));
  EXPECT_EQ(entry_parents(costs, 2, 1, 0, nodes, usable, 0), (std::vector<long>{}));  // entries off
  EXPECT_EQ(entry_parents(costs, 2, 0, 0, nodes, usable, 2), (std::vector<long>{4, 5}));  // the root is the parent
  EXPECT_EQ(entry_parents(costs, 2, 1, 4, nodes, usable, 2), (std::vector<long>{4, 5}));  // already a candidate
  const auto not_root = [](long node) { return node != 2 && node != 0; };
  EXPECT_EQ(entry_parents(costs, 2, 1, 0, nodes, not_root, 2), (std::vector<long>{4, 5}));
}

TEST(ParentRecovery, AnEntryCoveringClearlyMoreOrAsMuchAtALowerResidualReplacesTheKeptOne) {
  const FailureOptions failure;
  const double margin = failure.max_uncovered / 4;  // 0.25 % of the reconstruction, as the tree uses
  KeptAttempt kept{result_with(0.002, 0.006), 1, Verdict::pass};
  FrameRecord record;
  const auto attempt = [&](long from) -> std::optional<PairwiseResult> {
    if (from == 3) return result_with(0.0015, 0.006);   // as much uncovered, a lower residual: kept
    if (from == 4) return result_with(0.0018, 0.003);   // 0.3 % less uncovered: kept at a higher residual
    if (from == 5) return result_with(0.0010, 0.0056);  // 0.26 % more uncovered than 4: not kept
    if (from == 6) return std::nullopt;                 // threw
    if (from == 7) {                                    // failed (residual above 4 mm), recorded as the caller does
      record.failed_attempts.push_back({from, 0.005, 0.0, 0.0, "mean residual above the limit"});
      return result_with(0.005, 0.0);
    }
    return result_with(0.0017, 0.004);  // from 0: within the margin of 4, a lower residual: kept
  };
  const auto judge = [&](const PairwiseResult& r, long) { return verdict(r, 0.0, failure); };
  try_entry_candidates(kept, {3, 4, 5, 6, 7, 0}, margin, attempt, judge, record);
  EXPECT_EQ(kept.parent, 0);
  EXPECT_DOUBLE_EQ(kept.result->mean_residual, 0.0017);
  EXPECT_EQ(record.entry_attempts, 6);
  EXPECT_TRUE(record.failed_attempts.empty());
  // Without the margin rule, 5 (the lowest residual) would have been kept.
  KeptAttempt by_residual{result_with(0.002, 0.006), 1, Verdict::pass};
  try_entry_candidates(by_residual, {4, 5}, 1.0, attempt, judge, record);
  EXPECT_EQ(by_residual.parent, 5);
}

TEST(ParentRecovery, RetriesKeepTheLowestResidualThatDidNotFailAndStopAtAPass) {
  const FailureOptions failure;
  RecoveryOptions options;
  options.retries = 3;
  KeptAttempt kept{result_with(0.006), 1, Verdict::failed};
  std::vector<long> tried;
  const auto attempt = [&](long from) -> std::optional<PairwiseResult> {
    tried.push_back(from);
    if (from == 4) return std::nullopt;  // threw
    return result_with(from == 3 ? 0.0035 : 0.001);
  };
  const auto judge = [&](const PairwiseResult& r, long) { return verdict(r, 0.0025, failure); };
  retry_parents(kept, {4, 3, 5, 6}, options, attempt, judge);
  EXPECT_EQ(tried, (std::vector<long>{4, 3, 5}));  // 3 grew (kept over the failure), 5 passed: stop
  EXPECT_EQ(kept.parent, 5);
  EXPECT_EQ(kept.verdict, Verdict::pass);
}

TEST(ParentRecovery, WhenAllFailAnAlternativeReplacesTheTreeParentOnlyIfNoWorseByEveryCheck) {
  const FailureOptions failure;
  RecoveryOptions options;
  options.retries = 3;
  // The tree parent's attempt: folded onto itself (13 % stacked), 4.7 % uncovered.
  KeptAttempt kept{result_with(0.0028, 0.047, 0.131), 1, Verdict::failed};
  const auto attempt = [&](long from) -> std::optional<PairwiseResult> {
    if (from == 3) return result_with(0.0027, 0.048, 0.01);   // trades uncovered for stacked: no evidence
    if (from == 4) return result_with(0.0023, 0.002, 0.011);  // better by every check, still failing
    return result_with(0.0022, 0.003, 0.009);                 // failing, but worse than 4 in uncovered
  };
  const auto judge = [&](const PairwiseResult& r, long) { return verdict(r, 0.0, failure); };
  retry_parents(kept, {3, 4, 5}, options, attempt, judge);
  EXPECT_EQ(kept.parent, 4);
  EXPECT_EQ(kept.verdict, Verdict::failed);
  EXPECT_DOUBLE_EQ(kept.result->stacked_fraction, 0.011);
}

}  // namespace
}  // namespace surfcap::align
