// Scaling fits on synthetic data with known exponents: the estimates fall
// within their reported standard errors as often as standard errors should
// (about 68% of noise realisations), and the asymptotic range leaves out a
// low-density shoulder.
#include <wirefem/analysis/fits.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace
{
  using namespace wirefem::analysis;

  std::vector<double> linspace(const double a, const double b, const int n)
  {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i)
      v[i] = a + (b - a) * i / (n - 1);
    return v;
  }

  TEST(Fits, LoopExponentWithinItsErrorAsOftenAsAStandardError)
  {
    const double gamma = 1.8;
    const auto phi = linspace(0.1, 0.5, 60);
    int within = 0, realisations = 400;
    double mean_error = 0.0;
    for (int seed = 0; seed < realisations; ++seed)
      {
        // Counts: Poisson about 400 phi^1.8 (6 to 115 loops).
        std::mt19937 gen(seed);
        std::vector<double> loops(phi.size());
        for (std::size_t i = 0; i < phi.size(); ++i)
          loops[i] = std::poisson_distribution<int>(400.0 * std::pow(phi[i], gamma))(gen);
        const auto fit = fit_loop_exponent(phi, loops);
        ASSERT_TRUE(fit.ok) << fit.reason;
        within += std::abs(fit.gamma - gamma) <= fit.gamma_error;
        mean_error += fit.gamma_error / realisations;
      }
    const double fraction = static_cast<double>(within) / realisations;
    EXPECT_GT(fraction, 0.6);
    EXPECT_LT(fraction, 0.76);
    EXPECT_LT(mean_error, 0.08); // informative (about 0.06 here), not just wide
  }

  TEST(Fits, LoopExponentLeavesOutTheShoulder)
  {
    // A plateau of 2.5 loops below phi = 0.064 (the low-density shoulder
    // experiments show), a power law above it.
    const auto phi = linspace(0.01, 0.5, 80);
    std::vector<double> loops(phi.size());
    std::mt19937 gen(7);
    std::normal_distribution<double> noise(0.0, 0.03);
    for (std::size_t i = 0; i < phi.size(); ++i)
      loops[i] = std::max(2.5, 300.0 * std::pow(phi[i], 1.75)) * std::exp(noise(gen));
    const auto fit = fit_loop_exponent(phi, loops);
    ASSERT_TRUE(fit.ok) << fit.reason;
    EXPECT_GT(fit.phi_min, 0.064);
    EXPECT_LT(fit.phi_min, 0.15); // but not much more than the power law's range is left out
    EXPECT_NEAR(fit.gamma, 1.75, 3.0 * fit.gamma_error);
  }

  TEST(Fits, JammingForceWithinItsErrorsAsOftenAsStandardErrors)
  {
    const double phi_c = 0.46, beta = -1.43;
    const auto phi = linspace(0.2, 0.45, 50);
    int within_beta = 0, within_phi_c = 0, realisations = 300;
    for (int seed = 0; seed < realisations; ++seed)
      {
        std::mt19937 gen(seed);
        std::normal_distribution<double> noise(0.0, 0.03);
        std::vector<double> force(phi.size());
        for (std::size_t i = 0; i < phi.size(); ++i)
          force[i] = 0.5 * std::pow(phi_c - phi[i], beta) * std::exp(noise(gen));
        const auto fit = fit_jamming_force(phi, force, 0.0);
        ASSERT_TRUE(fit.ok) << fit.reason;
        within_beta += std::abs(fit.beta - beta) <= fit.beta_error;
        within_phi_c += std::abs(fit.phi_c - phi_c) <= fit.phi_c_error;
      }
    for (const int within : {within_beta, within_phi_c})
      {
        const double fraction = static_cast<double>(within) / realisations;
        EXPECT_GT(fraction, 0.58);
        EXPECT_LT(fraction, 0.78);
      }
  }

  TEST(Fits, SayWhyWhenTheyCannot)
  {
    EXPECT_FALSE(fit_loop_exponent({0.1, 0.2}, {1, 2}).ok);
    const auto f = fit_jamming_force({0.1, 0.2, 0.3}, {1, 2, 3}, 0.0);
    EXPECT_FALSE(f.ok);
    EXPECT_FALSE(f.reason.empty());
  }
} // namespace
