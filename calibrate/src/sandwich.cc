#include "sandwich.h"

#include <cmath>
#include <map>

namespace bouncecal::calibrate::internal {
namespace {

constexpr double kMaxCondition = 1e12;

// The inverse of a symmetric H, or nothing when it is not positive definite or too ill-conditioned.
bool InvertSymmetric(const Eigen::MatrixXd& h, Eigen::MatrixXd& inverse, double& condition) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(h);
  if (solver.info() != Eigen::Success) return false;
  const auto& values = solver.eigenvalues();
  if (!(values.minCoeff() > 0)) return false;
  condition = values.maxCoeff() / values.minCoeff();
  if (!(condition < kMaxCondition)) return false;
  inverse = solver.eigenvectors() * values.cwiseInverse().asDiagonal() *
            solver.eigenvectors().transpose();
  return true;
}

}  // namespace

CovarianceParts SandwichCovariance(const std::vector<SequenceLinearization>& sequences) {
  CovarianceParts parts;
  if (sequences.empty()) return parts;
  const Eigen::Index p = sequences.front().parameters.cols();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(p, p);
  Eigen::MatrixXd timing = Eigen::MatrixXd::Zero(p, p);
  Eigen::MatrixXd within = Eigen::MatrixXd::Zero(p, p);
  Eigen::MatrixXd between = Eigen::MatrixXd::Zero(p, p);
  std::map<int, Eigen::VectorXd> height_by_group;
  for (const auto& sequence : sequences) {
    const Eigen::MatrixXd jw = sequence.parameters.transpose() * sequence.weights.asDiagonal();
    h += jw * sequence.parameters;
    const Eigen::MatrixXd g = jw * sequence.onsets;  // p x onsets
    timing += g * sequence.onset_variance.asDiagonal() * g.transpose();
    const Eigen::MatrixXd ga = g * sequence.jitter;  // p x impacts
    within += ga * ga.transpose();
    const Eigen::VectorXd offset = ga.rowwise().sum();
    between += offset * offset.transpose();
    if (sequence.drop_height.size() > 0) {
      auto& height =
          height_by_group.try_emplace(sequence.drop_height_group, Eigen::VectorXd::Zero(p))
              .first->second;
      height += jw * sequence.drop_height;
    }
  }
  Eigen::MatrixXd inverse;
  if (!InvertSymmetric(h, inverse, parts.condition)) return parts;
  parts.ok = true;
  parts.timing = inverse * timing * inverse;
  parts.within = inverse * within * inverse;
  parts.between = inverse * between * inverse;
  parts.drop_height = Eigen::MatrixXd::Zero(p, p);
  for (const auto& [group, height] : height_by_group) {
    const Eigen::VectorXd shift = inverse * height;
    parts.drop_height += shift * shift.transpose();
  }
  return parts;
}

Eigen::VectorXd SingleSequenceStep(const SequenceLinearization& sequence) {
  const Eigen::MatrixXd jw = sequence.parameters.transpose() * sequence.weights.asDiagonal();
  Eigen::MatrixXd inverse;
  double condition = 0;
  if (!InvertSymmetric(jw * sequence.parameters, inverse, condition)) return {};
  return -inverse * (jw * sequence.residual);
}

}  // namespace bouncecal::calibrate::internal
