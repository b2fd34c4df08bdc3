#include "pteromys/coefficients.hpp"

#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "pteromys/aero.hpp"
#include "test_support.hpp"

using namespace pteromys;

namespace {

std::shared_ptr<RbfModel> random_rbf(std::mt19937& rng, int K, bool with_prior) {
  std::uniform_real_distribution<double> ua(deg2rad(-20), deg2rad(20)), ur(5e3, 6e4), ux(deg2rad(-50), deg2rad(50)),
      uc(-1, 1);
  std::vector<RbfCentre> cs;
  for (int k = 0; k < K; ++k) {
    RbfCentre c{ua(rng), ur(rng), ux(rng), ux(rng), {0.05 + 0.1 * std::abs(uc(rng)), uc(rng), 0.1 * uc(rng)}};
    cs.push_back(c);
  }
  return std::make_shared<RbfModel>(cs, RbfScales{}, deg2rad(30),
                                    with_prior ? std::make_shared<FlatPlateModel>() : nullptr);
}

bool bit_equal(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

// Paper eq. 3 with ghost centres: c_d(-a) == c_d(a) and c_l(-a) == -c_l(a),
// c_m(-a) == -c_m(a) exactly (bit for bit), for random models and inputs.
TEST(Coefficients, RbfParityIsExact) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ua(deg2rad(-40), deg2rad(40)), ur(1e3, 8e4), ux(deg2rad(-80), deg2rad(80));
  for (bool prior : {false, true}) {
    const auto m = random_rbf(rng, 12, prior);
    for (int i = 0; i < 2000; ++i) {
      const ElementState e{ua(rng), ur(rng), ux(rng), ux(rng)};
      ElementState f = e;
      f.alpha = -e.alpha;
      const Coefficients a = m->eval(e), b = m->eval(f);
      ASSERT_TRUE(bit_equal(a.cd, b.cd)) << a.cd << " " << b.cd;
      ASSERT_TRUE(bit_equal(a.cl, -b.cl)) << a.cl << " " << b.cl;
      ASSERT_TRUE(bit_equal(a.cm, -b.cm)) << a.cm << " " << b.cm;
    }
  }
}

TEST(Coefficients, FlatPlateParityIsExact) {
  const FlatPlateModel m;
  for (double a = -40; a <= 40; a += 0.37) {
    const Coefficients p = m.eval({deg2rad(a), 2e4, 0, 0}), q = m.eval({-deg2rad(a), 2e4, 0, 0});
    ASSERT_TRUE(bit_equal(p.cd, q.cd));
    ASSERT_TRUE(bit_equal(p.cl, -q.cl));
    ASSERT_TRUE(bit_equal(p.cm, -q.cm));
  }
}

// Interpolation: the Gaussian RBF reproduces its centre values (the kernel
// matrix is solved exactly), with and without a prior.
TEST(Coefficients, RbfReproducesCentreValues) {
  std::mt19937 rng(7);
  for (bool prior : {false, true}) {
    const auto m = random_rbf(rng, 10, prior);
    for (const auto& c : m->centres()) {
      const Coefficients v = m->eval({c.alpha, c.re, c.xi_l, c.xi_t});
      EXPECT_NEAR(v.cd, c.value.cd, 1e-8);
      EXPECT_NEAR(v.cl, c.value.cl, 1e-8);
      EXPECT_NEAR(v.cm, c.value.cm, 1e-8);
    }
  }
}

// Far from every centre the Gaussian terms vanish: the model returns its prior.
TEST(Coefficients, RbfFallsBackToPriorFarFromCentres) {
  std::mt19937 rng(3);
  const auto m = random_rbf(rng, 5, true);
  const FlatPlateModel fp;
  const ElementState far{deg2rad(5), 1e7, 0, 0};
  const Coefficients a = m->eval(far), b = fp.eval(far);
  EXPECT_NEAR(a.cd, b.cd, 1e-12);
  EXPECT_NEAR(a.cl, b.cl, 1e-12);
}

// Small-angle lift slope of the flat-plate element is Helmbold's finite-wing
// slope a = a0 / (sqrt(1 + (a0 / (pi A))^2) + a0 / (pi A)) (Helmbold 1942;
// e.g. Anderson, Fundamentals of Aerodynamics, eq. for low-aspect-ratio wings).
TEST(Coefficients, FlatPlateLiftSlopeIsHelmbold) {
  for (double A : {1.0, 3.0, 6.0}) {
    FlatPlateParams p;
    p.aspect_ratio = A;
    const FlatPlateModel m(p);
    const double a0 = p.section_lift_slope, k = a0 / (kPi * A);
    const double helmbold = a0 / (std::sqrt(1 + k * k) + k);
    const double h = deg2rad(0.01);
    const double slope = m.eval({h, 3e4, 0, 0}).cl / h;
    // The stall blend is already (slightly) active at alpha -> 0: 1e-3 relative.
    EXPECT_NEAR(slope, helmbold, 2e-3 * helmbold) << "A=" << A;
  }
}

// Laminar flat-plate friction (Blasius): C_f = 1.328 / sqrt(Re) per face.
TEST(Coefficients, FlatPlateZeroLiftDragIsBlasiusPlusEdges) {
  const FlatPlateModel m;
  for (double re : {5e3, 2e4, 1e5}) {
    const double cd0 = m.eval({0, re, 0, 0}).cd;
    EXPECT_NEAR(cd0, 2 * 1.328 / std::sqrt(re) + m.params().edge_drag, 1e-15);
  }
}

// The structure-aware sums (factorised Gaussian; Re-split flat plate) agree
// with the generic element-by-element sums.
TEST(Coefficients, FastSumsAgreeWithGenericSums) {
  std::mt19937 rng(11);
  const auto rbf = random_rbf(rng, 8, true);
  const FlatPlateModel fp;
  for (const auto& [path, g] : test::examples()) {
    const auto shapes = element_shapes(slice_wing(g.wings[0].outline, 0.01));
    const std::vector<double> rpc{1.2 * 3 / 1.8e-5, 1.2 * 9 / 1.8e-5};
    const std::vector<double> al{deg2rad(-12), deg2rad(-1), deg2rad(4), deg2rad(17)};
    for (const CoefficientModel* m : {static_cast<const CoefficientModel*>(rbf.get()),
                                      static_cast<const CoefficientModel*>(&fp)}) {
      CoefficientSums fast, slow;
      m->sum_over_elements(shapes, rpc, al, fast);
      m->CoefficientModel::sum_over_elements(shapes, rpc, al, slow);
      for (std::size_t i = 0; i < fast.cd_a.size(); ++i) {
        const double scale = std::abs(slow.cd_a[i]) + std::abs(slow.cl_a[i]) + 1e-9;
        EXPECT_NEAR(fast.cd_a[i], slow.cd_a[i], 1e-12 * scale) << path;
        EXPECT_NEAR(fast.cl_a[i], slow.cl_a[i], 1e-12 * scale) << path;
        EXPECT_NEAR(fast.cm_la[i], slow.cm_la[i], 1e-12 * scale) << path;
        EXPECT_NEAR(fast.cd_da[i], slow.cd_da[i], 1e-12 * scale) << path;
        EXPECT_NEAR(fast.cl_da[i], slow.cl_da[i], 1e-12 * scale) << path;
      }
    }
  }
}

TEST(Coefficients, RbfRejectsBadInput) {
  EXPECT_THROW(RbfModel({}, RbfScales{}, 0.5), InputError);
  RbfScales s;
  s.re = 0;
  EXPECT_THROW(RbfModel({RbfCentre{}}, s, 0.5), InputError);
  RbfCentre c;
  c.value.cl = std::nan("");
  EXPECT_THROW(RbfModel({c}, RbfScales{}, 0.5), InputError);
}
