#include "surfcap/align/parent_recovery.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "surfcap/align/tree_alignment.hpp"

namespace surfcap::align {

std::vector<long> candidate_parents(const Eigen::MatrixXd& costs, long child, long parent,
                                    const std::vector<NodeFrame>& nodes, const std::function<bool(long)>& usable,
                                    bool per_sequence) {
  std::vector<std::pair<double, long>> ranked;
  const long count = static_cast<long>(nodes.size());
  if (!per_sequence) {
    for (long other = 0; other < count; ++other)
      if (other != parent && usable(other)) ranked.push_back({costs(child, other), other});
  } else {
    const int parent_sequence = nodes[static_cast<std::size_t>(parent)].sequence;
    std::map<int, std::pair<double, long>> by_sequence;  // most similar usable frame per sequence
    for (long other = 0; other < count; ++other) {
      const int sequence = nodes[static_cast<std::size_t>(other)].sequence;
      if (sequence == parent_sequence || !usable(other)) continue;
      const double cost = costs(child, other);
      const auto found = by_sequence.find(sequence);
      if (found == by_sequence.end() || cost < found->second.first) by_sequence[sequence] = {cost, other};
    }
    for (const auto& entry : by_sequence) ranked.push_back(entry.second);
  }
  std::sort(ranked.begin(), ranked.end());
  std::vector<long> candidates;
  for (const auto& [cost, node] : ranked) candidates.push_back(node);
  return candidates;
}

namespace {

/// `a` no worse than `b` by every check (mean residual, uncovered and stacked fractions) and better
/// by one: evidence of a better alignment, where a lower failure score alone is not (one check
/// traded against another).
bool dominates(const PairwiseResult& a, const PairwiseResult& b) {
  const bool no_worse = a.mean_residual <= b.mean_residual && a.uncovered_fraction <= b.uncovered_fraction &&
                        a.stacked_fraction <= b.stacked_fraction;
  const bool better = a.mean_residual < b.mean_residual || a.uncovered_fraction < b.uncovered_fraction ||
                      a.stacked_fraction < b.stacked_fraction;
  return no_worse && better;
}

}  // namespace

std::optional<Verdict> keep_better(KeptAttempt& kept, std::optional<PairwiseResult> retry, long from,
                                   const VerdictFrom& verdict) {
  if (!retry) return std::nullopt;
  const Verdict v = verdict(*retry, from);
  // One that did not fail replaces one that did, or one with a higher mean residual; one that
  // failed replaces one that failed only when it fits no worse by every check.
  const bool usable = v != Verdict::failed;
  if (!kept.result || (usable && (kept.verdict == Verdict::failed || retry->mean_residual < kept.result->mean_residual)) ||
      (!usable && kept.verdict == Verdict::failed && dominates(*retry, *kept.result))) {
    kept.result = std::move(retry);
    kept.parent = from;
    kept.verdict = v;
  }
  return v;
}

void retry_parents(KeptAttempt& kept, const std::vector<long>& candidates, const RecoveryOptions& options,
                   const AttemptFrom& attempt, const VerdictFrom& verdict) {
  for (std::size_t k = 0; k < candidates.size() && static_cast<int>(k) < options.retries; ++k) {
    const long from = candidates[k];
    if (keep_better(kept, attempt(from), from, verdict) == Verdict::pass) break;
  }
}

std::vector<long> entry_parents(const Eigen::MatrixXd& costs, long child, long parent, long root,
                                const std::vector<NodeFrame>& nodes, const std::function<bool(long)>& usable,
                                int count) {
  std::vector<long> candidates = candidate_parents(costs, child, parent, nodes, usable, true);
  if (static_cast<long>(candidates.size()) > count) candidates.resize(static_cast<std::size_t>(std::max(count, 0)));
  const bool listed = std::find(candidates.begin(), candidates.end(), root) != candidates.end();
  if (count > 0 && root != parent && !listed && usable(root)) candidates.push_back(root);
  return candidates;
}

void try_entry_candidates(KeptAttempt& kept, const std::vector<long>& candidates, double uncovered_margin,
                          const AttemptFrom& attempt, const VerdictFrom& verdict, FrameRecord& record) {
  for (const long from : candidates) {
    const std::size_t failures = record.failed_attempts.size();
    std::optional<PairwiseResult> alternative = attempt(from);
    record.failed_attempts.resize(failures);
    ++record.entry_attempts;
    if (!alternative || verdict(*alternative, from) != Verdict::pass) continue;
    const double less_uncovered = kept.result->uncovered_fraction - alternative->uncovered_fraction;
    const bool covers_more = less_uncovered > uncovered_margin;
    const bool covers_as_much = std::abs(less_uncovered) <= uncovered_margin;
    if (covers_more || (covers_as_much && alternative->mean_residual < kept.result->mean_residual)) {
      kept.result = std::move(alternative);
      kept.parent = from;
    }
  }
}

}  // namespace surfcap::align
