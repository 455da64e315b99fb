// Scaling fits (docs/analysis.md, Fits), with uncertainties, by GSL's least squares.
#pragma once

#include <string>
#include <vector>

namespace wirefem::analysis
{
  /// N_l = c phi^gamma, by weighted linear least squares of log N_l on
  /// log phi (weights: the fitted N_l, for counting noise var log N ~ 1/N).
  struct LoopFit
  {
    bool ok = false;
    std::string reason; ///< why not, when !ok
    double gamma = 0.0, gamma_error = 0.0;
    double log_prefactor = 0.0, log_prefactor_error = 0.0;
    double phi_min = 0.0, phi_max = 0.0; ///< the asymptotic range used
    int n_points = 0;
  };

  /// Fits gamma over the asymptotic range: the widest range of rows (in
  /// log phi) that spans at least `min_ratio` in phi and
  /// `min_points` rows with N_l >= min_loops (the log of fewer counts is
  /// biased by the counting noise), and on which log N_l shows no
  /// curvature in log phi (a quadratic term within two standard errors of
  /// zero). More than 60 rows are first averaged in 60 bins of equal width
  /// in log phi. Errors are one standard error from the weighted scatter
  /// about the line; successive rows of one run are correlated, so for run
  /// data they are a lower bound.
  LoopFit fit_loop_exponent(const std::vector<double> &phi, const std::vector<double> &loops,
                            int min_points = 8, double min_ratio = 1.5, double min_loops = 5);

  /// F = A (phi_c - phi)^beta (beta < 0: F diverges at phi_c), by nonlinear
  /// least squares of log F (GSL multifit_nlinear, trust region), with
  /// phi_c kept above the largest phi of the data.
  struct JammingFit
  {
    bool ok = false;
    std::string reason;
    double phi_c = 0.0, phi_c_error = 0.0;
    double beta = 0.0, beta_error = 0.0;
    double log_prefactor = 0.0, log_prefactor_error = 0.0;
    double phi_min = 0.0, phi_max = 0.0;
    int n_points = 0;
  };

  /// Uses the rows with phi >= phi_min and F > 0. Errors are one standard
  /// error from the covariance at the optimum scaled by chi^2/dof.
  JammingFit fit_jamming_force(const std::vector<double> &phi, const std::vector<double> &force,
                               double phi_min);
} // namespace wirefem::analysis
