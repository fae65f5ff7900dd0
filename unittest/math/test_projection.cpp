// Unit tests for the PCVA momentum scaling (src/HARDSPHERE/hs_projection.h,
// Bond & Leimkuhler 2007, section 3.2) and the pieces of H_[2,VV].
//
// Expected values: for the harmonic oscillator V = k q^2/2 velocity Verlet
// has the exact quadratic invariant I = p^2/2m + k q^2/2 (1 - w^2 dt^2/4),
// and H + dt^2/24 H2 (the paper's H2 = 2 p V'' p/m^2 - V'^2/m written out by
// hand) equals (1 + a) I + 3/2 a^2 k q^2/2, a = w^2 dt^2/6, so Verlet steps
// of size dt keep H_[2,VV] to a known O(dt^4) bound, steps of another size
// break it at O(dt^3), and the scaling must restore it to round-off. Cases
// without a real positive root must be reported.

#include "hs_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace HardSphere;

namespace {

constexpr double EPS = std::numeric_limits<double>::epsilon();

// harmonic oscillator: parts of H_[2,VV] at (q, p)
ModifiedEnergyParts ho_parts(double q, double p, double m, double k)
{
  const double v = p / m, g = k * q;
  return {0.5 * p * p / m, v * k * v, 0.5 * k * q * q, g * g / m};
}

// one Verlet step of size tau (section 3's kick-drift-kick)
void verlet(double &q, double &p, double m, double k, double tau)
{
  p -= 0.5 * tau * k * q;
  q += tau * p / m;
  p -= 0.5 * tau * k * q;
}

}    // namespace

TEST(Projection, HarmonicOscillatorModifiedHamiltonianMatchesVerletInvariant)
{
  const double m = 1.7, k = 2.3, w2 = k / m;
  double prev = -1.0;
  for (double dt : {0.2, 0.1, 0.05}) {
    double q = 0.8, p = -0.4;
    // the pieces against the paper's formula written out
    const ModifiedEnergyParts e0 = ho_parts(q, p, m, k);
    const double H = p * p / (2 * m) + 0.5 * k * q * q;
    const double H2 = 2 * p * p / (m * m) * k - k * q * k * q / m;
    EXPECT_NEAR(modified_hamiltonian2(e0, dt), H + dt * dt / 24.0 * H2, 8 * EPS * H);
    // against the exact invariant of Verlet: with a = w^2 dt^2/6,
    // H_[2,VV] = (1 + a) I + 3/2 a^2 k q^2/2 identically
    const double a = w2 * dt * dt / 6;
    auto I = [&](double qq, double pp) {
      return pp * pp / (2 * m) + 0.5 * k * qq * qq * (1 - w2 * dt * dt / 4);
    };
    EXPECT_NEAR(modified_hamiltonian2(e0, dt), (1 + a) * I(q, p) + 1.5 * a * a * 0.5 * k * q * q,
                8 * EPS * H);
    // so Verlet keeps H_[2,VV] to O(dt^4): the deviation is 3/2 a^2 times
    // the variation of k q^2/2, which is at most I / (1 - w^2 dt^2/4)
    const double Ht0 = modified_hamiltonian2(e0, dt);
    const double I0 = I(q, p);
    double maxdev = 0.0;
    for (int n = 0; n < 1000; n++) {
      verlet(q, p, m, k, dt);
      EXPECT_NEAR(I(q, p), I0, 64 * EPS * I0);
      maxdev = std::max(maxdev, std::fabs(modified_hamiltonian2(ho_parts(q, p, m, k), dt) - Ht0));
    }
    EXPECT_LE(maxdev, 1.5 * a * a * I0 / (1 - w2 * dt * dt / 4) * (1 + 1e-9)) << "dt " << dt;
    EXPECT_GT(maxdev, 0.5 * 1.5 * a * a * I0) << "dt " << dt;
    if (prev > 0) EXPECT_NEAR(prev / maxdev, 16.0, 1.0) << "fourth order in dt";
    prev = maxdev;
  }
}

TEST(Projection, ScalingRestoresModifiedHamiltonianAfterOffStepSubsteps)
{
  const double m = 1.0, k = 1.0, dt = 0.2;
  double q = 0.3, p = 1.1;
  const double target = modified_hamiltonian2(ho_parts(q, p, m, k), dt);
  // sub-steps of other sizes (as around a collision) change H_[2,VV] at O(dt^3)
  const double taus[] = {0.07, 0.13, 0.2 - 0.07};
  for (double tau : taus) {
    verlet(q, p, m, k, tau);
    const ModifiedEnergyParts e = ho_parts(q, p, m, k);
    const double before = modified_hamiltonian2(e, dt);
    EXPECT_GT(std::fabs(before - target), 1e-6);
    double alpha;
    ASSERT_EQ(pcva_scale(target, modified_potential(e, dt), modified_kinetic(e, dt), alpha), SCALE_OK);
    // closed form of the root
    const double Kt = 0.5 * p * p / m + dt * dt / 12 * k * p * p / (m * m);
    const double U = 0.5 * k * q * q - dt * dt / 24 * k * k * q * q / m;
    EXPECT_NEAR(alpha, std::sqrt((target - U) / Kt), 4 * EPS);
    EXPECT_NEAR(alpha, 1.0, 1e-2);
    p *= alpha;
    EXPECT_NEAR(modified_hamiltonian2(ho_parts(q, p, m, k), dt), target, 8 * EPS * target);
  }
}

TEST(Projection, ScalingInManyDimensionsFromScratch)
{
  // random masses, a random symmetric V'' and gradient: H_[2,VV](q, alpha p)
  // recomputed from scratch must equal the target
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 9;
  const double dt = 0.05;
  for (int trial = 0; trial < 200; trial++) {
    std::vector<double> m(n), p(n), g(n), A(n * n);
    for (int i = 0; i < n; i++) {
      m[i] = 0.5 + std::fabs(u(rng));
      p[i] = u(rng);
      g[i] = u(rng);
    }
    for (int i = 0; i < n; i++)
      for (int j = 0; j <= i; j++) A[i * n + j] = A[j * n + i] = u(rng) + (i == j ? 3.0 : 0.0);
    const double V = u(rng);
    auto parts = [&](double s) {
      ModifiedEnergyParts e{0, 0, V, 0};
      for (int i = 0; i < n; i++) {
        e.kin += 0.5 * s * p[i] * s * p[i] / m[i];
        e.g2 += g[i] * g[i] / m[i];
        for (int j = 0; j < n; j++) e.vhv += s * p[i] / m[i] * A[i * n + j] * s * p[j] / m[j];
      }
      return e;
    };
    const ModifiedEnergyParts e = parts(1.0);
    const double target = modified_hamiltonian2(e, dt) * (1.0 + 0.3 * u(rng));
    double alpha;
    const ScaleStatus st = pcva_scale(target, modified_potential(e, dt), modified_kinetic(e, dt), alpha);
    if (target > modified_potential(e, dt)) {
      ASSERT_EQ(st, SCALE_OK);
      EXPECT_GT(alpha, 0.0);
      EXPECT_NEAR(modified_hamiltonian2(parts(alpha), dt), target,
                  64 * EPS * (std::fabs(target) + e.kin + std::fabs(V)));
    } else {
      EXPECT_EQ(st, SCALE_NO_ROOT);
      EXPECT_EQ(alpha, 1.0);
    }
  }
}

TEST(Projection, NoRealRootIsReported)
{
  double alpha = -5.0;
  // H~0 below U: alpha^2 < 0
  EXPECT_EQ(pcva_scale(1.0, 2.0, 0.5, alpha), SCALE_NO_ROOT);
  EXPECT_EQ(alpha, 1.0);
  // H~0 == U: alpha = 0 would stop everything; not a valid projection
  EXPECT_EQ(pcva_scale(2.0, 2.0, 0.5, alpha), SCALE_NO_ROOT);
  // K~ <= 0: strongly negative curvature along v with a large dt
  ModifiedEnergyParts e{0.5, -100.0, 0.0, 0.0};
  EXPECT_LT(modified_kinetic(e, 0.3), 0.0);
  EXPECT_EQ(pcva_scale(1.0, 0.0, modified_kinetic(e, 0.3), alpha), SCALE_BAD_KINETIC);
  EXPECT_EQ(pcva_scale(1.0, 0.0, 0.0, alpha), SCALE_BAD_KINETIC);
  EXPECT_EQ(pcva_scale(1.0, 0.0, NAN, alpha), SCALE_BAD_KINETIC);
  EXPECT_EQ(pcva_scale(NAN, 0.0, 1.0, alpha), SCALE_NO_ROOT);
  EXPECT_EQ(alpha, 1.0);
  // a plain case
  EXPECT_EQ(pcva_scale(3.0, 1.0, 0.5, alpha), SCALE_OK);
  EXPECT_DOUBLE_EQ(alpha, 2.0);
}

// the local projection's beta (substep local): a harmonic pair whose
// relative velocity b is scaled, v -> v + beta b. With the kinetic energy
// K(b) and the curvature term written out, dH~(beta) = A beta^2 + B beta
// + C0 exactly; the returned root makes it vanish and is the one near 0
TEST(Projection, LocalBetaIsTheSmallRootOfTheExactQuadratic)
{
  // two unit masses, spring constant k along x, dt: relative velocity u
  const double k = 3.0, dt = 0.1, u = 0.7, m = 1.0;
  // velocities +-u/2 about a resting centre of mass: b = v
  const double mb2 = 2.0 * m * (u / 2) * (u / 2);
  const double btKb = k * u * u;    // (b_1 - b_2) k (b_1 - b_2)
  const double A = 0.5 * mb2 + dt * dt / 12.0 * btKb;
  const double B = mb2 + dt * dt / 6.0 * btKb;    // b^T K v = b^T K b here
  for (double C0 : {1e-6, -1e-6, 1e-3, -0.05}) {
    double beta = 99.0;
    ASSERT_EQ(pcva_local_beta(A, B, C0, beta), SCALE_OK) << C0;
    // H~ of the scaled state, from scratch: (1 + beta)^2 times that of v
    const double Kt = 0.5 * mb2 + dt * dt / 12.0 * btKb;
    const double change = (1 + beta) * (1 + beta) * Kt - Kt + C0;
    EXPECT_NEAR(change, 0.0, 1e-15) << C0;
    EXPECT_LT(std::fabs(beta), 1.0) << "the root near zero, not the one near -2";
  }
  double beta = 1.0;
  // more to undo than the relative motion holds: no real root
  EXPECT_EQ(pcva_local_beta(A, B, 10.0, beta), SCALE_NO_ROOT);
  EXPECT_EQ(beta, 0.0);
  // no relative motion, or K~(b) <= 0
  EXPECT_EQ(pcva_local_beta(0.0, 0.0, 1e-6, beta), SCALE_BAD_KINETIC);
  EXPECT_EQ(pcva_local_beta(-1.0, 1.0, 1e-6, beta), SCALE_BAD_KINETIC);
  EXPECT_EQ(pcva_local_beta(1.0, NAN, 1e-6, beta), SCALE_BAD_KINETIC);
}
