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
