#include <wirefem/analysis/fits.h>

#include <fmt/format.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_fit.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_multifit_nlinear.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace wirefem::analysis
{
  namespace
  {
    /// Quadratic coefficient of log N on log phi and its standard error.
    std::pair<double, double> curvature(const std::vector<double> &x, const std::vector<double> &y,
                                        const std::vector<double> &weight)
    {
      const std::size_t n = x.size();
      std::unique_ptr<gsl_matrix, decltype(&gsl_matrix_free)> X(gsl_matrix_alloc(n, 3), gsl_matrix_free);
      std::unique_ptr<gsl_vector, decltype(&gsl_vector_free)> Y(gsl_vector_alloc(n), gsl_vector_free),
          W(gsl_vector_alloc(n), gsl_vector_free), c(gsl_vector_alloc(3), gsl_vector_free);
      std::unique_ptr<gsl_matrix, decltype(&gsl_matrix_free)> cov(gsl_matrix_alloc(3, 3), gsl_matrix_free);
      std::unique_ptr<gsl_multifit_linear_workspace, decltype(&gsl_multifit_linear_free)> work(
          gsl_multifit_linear_alloc(n, 3), gsl_multifit_linear_free);
      const double x0 = 0.5 * (x.front() + x.back()); // centred: a well-conditioned basis
      for (std::size_t i = 0; i < n; ++i)
        {
          const double u = x[i] - x0;
          gsl_matrix_set(X.get(), i, 0, 1.0);
          gsl_matrix_set(X.get(), i, 1, u);
          gsl_matrix_set(X.get(), i, 2, u * u);
          gsl_vector_set(Y.get(), i, y[i]);
          gsl_vector_set(W.get(), i, weight[i]);
        }
      double chisq = 0.0;
      gsl_multifit_wlinear(X.get(), W.get(), Y.get(), c.get(), cov.get(), &chisq, work.get());
      // The weights are relative: scale the covariance by chi^2/dof.
      const double scale = n > 3 ? chisq / (n - 3) : 0.0;
      return {gsl_vector_get(c.get(), 2), std::sqrt(std::max(0.0, scale * gsl_matrix_get(cov.get(), 2, 2)))};
    }
  } // namespace

  namespace
  {
    /// The rows (log phi, loops) as points (log phi, log loops): each row
    /// its own point, or averaged in at most 60 bins of equal width in log phi.
    void bin_rows(const std::vector<std::pair<double, double>> &rows, std::vector<double> &x,
                  std::vector<double> &y, std::vector<double> &count)
    {
      // Many rows (long runs, pooled realizations) are averaged in at most
      // max_bins bins of equal width in log phi: successive rows of a run are
      // correlated anyway, and the window search below is quadratic in them.
      constexpr int max_bins = 60;
      if (static_cast<int>(rows.size()) <= max_bins)
        for (const auto &[lx, nl] : rows)
          {
            x.push_back(lx);
            y.push_back(std::log(nl));
            count.push_back(1.0);
          }
      else
        {
          const double x0 = rows.front().first, width = (rows.back().first - x0) / max_bins;
          std::size_t i = 0;
          for (int b = 0; b < max_bins; ++b)
            {
              double sx = 0.0, sn = 0.0;
              int m = 0;
              while (i < rows.size() && (b == max_bins - 1 || rows[i].first < x0 + (b + 1) * width))
                {
                  sx += rows[i].first;
                  sn += rows[i].second;
                  ++m;
                  ++i;
                }
              if (m == 0)
                continue;
              x.push_back(sx / m);
              y.push_back(std::log(sn / m));
              count.push_back(m);
            }
        }
    }

    /// The widest window [start, end) of the points, at least min_points
    /// long and spanning a factor min_ratio in phi, without detectable
    /// curvature; (-1, -1) when there is none.
    std::pair<int, int> widest_straight_window(const std::vector<double> &x, const std::vector<double> &y,
                                               const std::vector<double> &w, const int min_points,
                                               const double min_ratio)
    {
      const int n = static_cast<int>(x.size());
      int start = -1, end = -1;
      double widest = std::log(min_ratio);
      for (int s0 = 0; s0 + min_points <= n; ++s0)
        for (int e = n; e - s0 >= min_points; --e)
          {
            const double span = x[e - 1] - x[s0];
            if (span < widest || (span == widest && e - s0 <= end - start))
              break; // shorter windows from s0 only get narrower
            const std::vector<double> xs(x.begin() + s0, x.begin() + e), ys(y.begin() + s0, y.begin() + e),
                ws(w.begin() + s0, w.begin() + e);
            const auto [c2, e2] = curvature(xs, ys, ws);
            if (std::abs(c2) <= 2.0 * e2 + 1e-12) // (exact data: no curvature at all)
              {
                start = s0;
                end = e;
                widest = span;
                break;
              }
          }
      return {start, end};
    }
  } // namespace

  LoopFit fit_loop_exponent(const std::vector<double> &phi, const std::vector<double> &loops,
                            const int min_points, const double min_ratio, const double min_loops)
  {
    LoopFit fit;
    // Rows with enough loops, in order of phi.
    std::vector<std::pair<double, double>> rows;
    for (std::size_t i = 0; i < phi.size() && i < loops.size(); ++i)
      if (phi[i] > 0.0 && loops[i] >= min_loops)
        rows.emplace_back(std::log(phi[i]), loops[i]);
    std::sort(rows.begin(), rows.end());
    std::vector<double> x, y, w, count;
    bin_rows(rows, x, y, count);
    // Counting noise: var(log N) ~ 1/N, so a point weighs N times its rows.
    for (std::size_t i = 0; i < x.size(); ++i)
      w.push_back(std::exp(y[i]) * count[i]);
    const int n = static_cast<int>(x.size());
    if (n < min_points)
      {
        fit.reason =
            fmt::format("fewer than {} rows (or bins) with at least {} loops", min_points, min_loops);
        return fit;
      }
    const auto [start, end] = widest_straight_window(x, y, w, min_points, min_ratio);
    if (start < 0)
      {
        fit.reason = fmt::format("no range without curvature spans a factor {} in phi", min_ratio);
        return fit;
      }
    const std::size_t m = end - start;
    double c0, c1, cov00, cov01, cov11, chisq;
    gsl_fit_wlinear(x.data() + start, 1, w.data() + start, 1, y.data() + start, 1, m, &c0, &c1, &cov00,
                    &cov01, &cov11, &chisq);
    // Reweight with the fitted counts (the observed ones weigh a low
    // fluctuation less, which biases the slope), twice.
    for (int pass = 0; pass < 2; ++pass)
      {
        for (int i = start; i < end; ++i)
          w[i] = std::exp(c0 + c1 * x[i]) * count[i];
        gsl_fit_wlinear(x.data() + start, 1, w.data() + start, 1, y.data() + start, 1, m, &c0, &c1, &cov00,
                        &cov01, &cov11, &chisq);
      }
    const double scale = m > 2 ? chisq / (m - 2) : 0.0; // relative weights
    fit.ok = true;
    fit.gamma = c1;
    fit.gamma_error = std::sqrt(scale * cov11);
    fit.log_prefactor = c0;
    fit.log_prefactor_error = std::sqrt(scale * cov00);
    fit.phi_min = std::exp(x[start]);
    fit.phi_max = std::exp(x[end - 1]);
    fit.n_points = static_cast<int>(m);
    return fit;
  }

  namespace
  {
    struct JammingData
    {
      std::vector<double> phi, log_force;
      double phi_top;
    };

    // Parameters p = (log A, q, beta) with phi_c = phi_top + exp(q).
    int jamming_residual(const gsl_vector *p, void *params, gsl_vector *r)
    {
      const auto &d = *static_cast<const JammingData *>(params);
      const double a = gsl_vector_get(p, 0), q = gsl_vector_get(p, 1), beta = gsl_vector_get(p, 2);
      const double phi_c = d.phi_top + std::exp(q);
      for (std::size_t i = 0; i < d.phi.size(); ++i)
        gsl_vector_set(r, i, a + beta * std::log(phi_c - d.phi[i]) - d.log_force[i]);
      return GSL_SUCCESS;
    }

    int jamming_jacobian(const gsl_vector *p, void *params, gsl_matrix *J)
    {
      const auto &d = *static_cast<const JammingData *>(params);
      const double q = gsl_vector_get(p, 1), beta = gsl_vector_get(p, 2);
      const double phi_c = d.phi_top + std::exp(q);
      for (std::size_t i = 0; i < d.phi.size(); ++i)
        {
          const double gap = phi_c - d.phi[i];
          gsl_matrix_set(J, i, 0, 1.0);
          gsl_matrix_set(J, i, 1, beta * std::exp(q) / gap);
          gsl_matrix_set(J, i, 2, std::log(gap));
        }
      return GSL_SUCCESS;
    }
  } // namespace

  JammingFit fit_jamming_force(const std::vector<double> &phi, const std::vector<double> &force,
                               const double phi_min)
  {
    JammingFit fit;
    JammingData d;
    for (std::size_t i = 0; i < phi.size() && i < force.size(); ++i)
      if (phi[i] >= phi_min && force[i] > 0.0 && std::isfinite(force[i]))
        {
          d.phi.push_back(phi[i]);
          d.log_force.push_back(std::log(force[i]));
        }
    const std::size_t n = d.phi.size();
    if (n < 6)
      {
        fit.reason = "fewer than 6 rows with a positive force";
        return fit;
      }
    d.phi_top = *std::max_element(d.phi.begin(), d.phi.end());
    const double span = d.phi_top - *std::min_element(d.phi.begin(), d.phi.end());
    if (span <= 0.0)
      {
        fit.reason = "the rows span no range of phi";
        return fit;
      }

    gsl_multifit_nlinear_fdf fdf;
    fdf.f = jamming_residual;
    fdf.df = jamming_jacobian;
    fdf.fvv = nullptr;
    fdf.n = n;
    fdf.p = 3;
    fdf.params = &d;
    auto parameters = gsl_multifit_nlinear_default_parameters();
    std::unique_ptr<gsl_multifit_nlinear_workspace, decltype(&gsl_multifit_nlinear_free)> w(
        gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &parameters, n, 3), gsl_multifit_nlinear_free);
    // Start: phi_c a tenth of the span above the data, beta = -1.5, A from the mean.
    const double q0 = std::log(0.1 * span), beta0 = -1.5;
    double a0 = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      a0 += (d.log_force[i] - beta0 * std::log(d.phi_top + std::exp(q0) - d.phi[i])) / n;
    double start[3] = {a0, q0, beta0};
    gsl_vector_view x0 = gsl_vector_view_array(start, 3);
    gsl_multifit_nlinear_init(&x0.vector, &fdf, w.get());
    int info = 0;
    const auto handler = gsl_set_error_handler_off();
    const int status =
        gsl_multifit_nlinear_driver(500, 1e-10, 1e-10, 1e-10, nullptr, nullptr, &info, w.get());
    gsl_set_error_handler(handler);
    if (status != GSL_SUCCESS)
      {
        fit.reason = std::string("least squares did not converge: ") + gsl_strerror(status);
        return fit;
      }
    const gsl_vector *p = gsl_multifit_nlinear_position(w.get());
    std::unique_ptr<gsl_matrix, decltype(&gsl_matrix_free)> cov(gsl_matrix_alloc(3, 3), gsl_matrix_free);
    gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(w.get()), 0.0, cov.get());
    double chisq = 0.0;
    gsl_blas_ddot(gsl_multifit_nlinear_residual(w.get()), gsl_multifit_nlinear_residual(w.get()), &chisq);
    const double scale = n > 3 ? chisq / (n - 3) : 0.0;
    const double q = gsl_vector_get(p, 1);
    fit.ok = true;
    fit.log_prefactor = gsl_vector_get(p, 0);
    fit.log_prefactor_error = std::sqrt(scale * gsl_matrix_get(cov.get(), 0, 0));
    fit.phi_c = d.phi_top + std::exp(q);
    fit.phi_c_error = std::exp(q) * std::sqrt(scale * gsl_matrix_get(cov.get(), 1, 1));
    fit.beta = gsl_vector_get(p, 2);
    fit.beta_error = std::sqrt(scale * gsl_matrix_get(cov.get(), 2, 2));
    fit.phi_min = *std::min_element(d.phi.begin(), d.phi.end());
    fit.phi_max = d.phi_top;
    fit.n_points = static_cast<int>(n);
    return fit;
  }
} // namespace wirefem::analysis
