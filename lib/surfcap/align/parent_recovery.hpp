#pragma once
// Parent recovery: a child whose alignment from its tree parent failed (pairwise_checks.hpp) is
// aligned again from the next most similar frames already aligned; an edge entering the child's
// sequence from another — two sequences' poses can look alike to the shape histograms with a limb
// far apart — is also aligned from the most similar aligned frame of a few other sequences and
// from the root.

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <vector>

#include "surfcap/align/motion_prediction.hpp"
#include "surfcap/align/pairwise_alignment.hpp"
#include "surfcap/core/option_table.hpp"

namespace surfcap::align {

struct FrameRecord;

/// Up to `retries` alternative parents for a failed child; of the attempts that did not fail the
/// lowest mean residual is kept, and if all failed the tree parent's unless another fits no worse
/// by every check and better by one (a lower failure score alone is no evidence of a better
/// alignment: it may trade one check for another). Up to `entry_candidates` other sequences, and
/// the root, tried for an edge between sequences (0: none).
struct RecoveryOptions {
  int retries = 2;
  int entry_candidates = 2;

  template <class Self, class Table>
  static void table(Self& self, Table& t) {
    t.field("retries", self.retries, "Alternative parents tried for a failed frame", core::Range::closed(0, 10));
    t.field("entry_candidates", self.entry_candidates,
            "An edge from another sequence is also aligned from the most similar frame of up to N other sequences "
            "and from the root",
            core::Range::closed(0, 10));
  }
};

/// The attempt kept for a child so far: the result (nullopt: every attempt threw), where from and
/// its verdict.
struct KeptAttempt {
  std::optional<PairwiseResult> result;
  long parent = -1;
  Verdict verdict = Verdict::failed;
};

/// One attempt from a node (nullopt if it threw; failures are recorded by the caller) and the
/// verdict on a result from a node.
using AttemptFrom = std::function<std::optional<PairwiseResult>(long from)>;
using VerdictFrom = std::function<Verdict(const PairwiseResult& result, long from)>;

/// Candidate parents of `child` by similarity cost (`costs` row), cheapest first (ties: lower
/// node), among the nodes `usable` accepts other than `parent`: for a retry (`per_sequence` false)
/// every such node, for an entry (true) only the cheapest of each sequence other than the parent's.
std::vector<long> candidate_parents(const Eigen::MatrixXd& costs, long child, long parent,
                                    const std::vector<NodeFrame>& nodes, const std::function<bool(long)>& usable,
                                    bool per_sequence);

/// Keeps `retry` (an attempt from `from`; nullopt: it threw) instead of the kept attempt by the
/// rules above; returns its verdict (nullopt if it threw).
std::optional<Verdict> keep_better(KeptAttempt& kept, std::optional<PairwiseResult> retry, long from,
                                   const VerdictFrom& verdict);

/// Retries from `candidates` (the first `options.retries`), stopping at the first that passes.
void retry_parents(KeptAttempt& kept, const std::vector<long>& candidates, const RecoveryOptions& options,
                   const AttemptFrom& attempt, const VerdictFrom& verdict);

/// The other parents of an edge entering the child's sequence from another: the most similar
/// usable frame of up to `count` other sequences (candidate_parents), then the root unless it is
/// the parent, among them or not usable. The root is the one frame aligned without error: a
/// sequence entered from it does not inherit the error of another sequence's chain.
std::vector<long> entry_parents(const Eigen::MatrixXd& costs, long child, long parent, long root,
                                const std::vector<NodeFrame>& nodes, const std::function<bool(long)>& usable,
                                int count);

/// Aligns from each of `candidates`: one that passes replaces the kept attempt when it leaves
/// more than `uncovered_margin` less of the reconstruction uncovered — surface the template did
/// not follow, which the mean residual (over the template) can miss: two entries can fit at the
/// same residual — or, leaving as much uncovered (within the margin either way), when its mean
/// residual is lower. An alternative that fails is no failure of the
/// frame (`record` keeps only the count).
void try_entry_candidates(KeptAttempt& kept, const std::vector<long>& candidates, double uncovered_margin,
                          const AttemptFrom& attempt, const VerdictFrom& verdict, FrameRecord& record);

}  // namespace surfcap::align
