// Coefficient fitting (paper eq. 6) with the launch fits (eq. 5) and greedy
// insertion of RBF centres (Bickel et al. 2009).
//
// The coefficient values at the centres are the unknowns of a nonlinear
// least-squares problem solved by Levenberg-Marquardt (Eigen's MINPACK port).
// Each residual evaluation rebuilds the force tables of every glider for the
// new values (the RBF table build is factorised) and re-simulates every
// flight; the Jacobian is taken by forward differences, one column per value,
// columns in parallel.
//
// Launches and coefficients are strongly coupled (a launch's pitch trades
// against the pitching moment, its speed against the drag), so alternating
// between the two fits converges slowly. When every launch is fitted to all
// points of its flight (the default), both fits minimise the same error E and
// the problem is solved jointly by variable projection (Golub & Pereyra
// 1973): every residual evaluation re-fits the launches for the new values,
// and the Jacobian with respect to the values is projected, flight by flight,
// onto the complement of the launch Jacobian (Kaufman 1975). With the paper's
// M = 10 the two fits minimise different errors and are alternated as in the
// paper.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <thread>

#include <Eigen/Dense>
#include <unsupported/Eigen/LevenbergMarquardt>

#include "pteromys/elements.hpp"
#include "pteromys/fit.hpp"
#include "pteromys/mass.hpp"

#include "parallel.hpp"

namespace pteromys {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string fmt(double v, int prec = 4) {
  std::ostringstream s;
  s.precision(prec);
  s << v;
  return s.str();
}

using detail::parallel_for;

/// Scale of each coefficient in the solver's units: cd, cl, cm.
constexpr double kScale[3] = {0.02, 0.1, 0.02};
/// Forward-difference step in scaled units.
constexpr double kStep = 1e-3;
/// Weight of the bound penalty [m per scale unit beyond a bound].
constexpr double kBoundWeight = 10.0;

double coef(const Coefficients& c, int i) { return i == 0 ? c.cd : i == 1 ? c.cl : c.cm; }
void set_coef(Coefficients& c, int i, double v) { (i == 0 ? c.cd : i == 1 ? c.cl : c.cm) = v; }

struct GliderCtx {
  std::string key;
  const Glider* glider = nullptr;
  MassProperties mass;
  RigidBody body;
  std::vector<Mount> mounts;
  std::vector<WingElements> wings;
  std::vector<std::size_t> flights;
};

struct FlightCtx {
  const TrackedFlight* f = nullptr;
  int glider = 0;
  std::vector<double> times;
  std::vector<Vec2> q;
  std::vector<TrackedPoint> points;
  int offset = 0;  // index of the flight's first point among all points
};

struct Eval {
  double sse = 0;            // raw sum of squared distances [m^2]
  Eigen::VectorXd r;         // weighted residuals (data, regularisation, bounds)
};

class Fitter {
 public:
  Fitter(const Dataset& d, const FitOptions& o, const FitCallback& cb)
      : d_(d), o_(o), cb_(cb), t0_(Clock::now()) {
    if (d.flights.empty()) throw InputError("the dataset has no flights to fit");
    const auto problems = dataset_problems(d);
    if (!problems.empty()) throw InputError("invalid dataset: " + problems.front());
    if (o.max_centres < 1 || o.max_centres > 200) throw InputError("the number of centres must be between 1 and 200");
    if (o.launch.points != 0 && o.launch.points < 3)
      throw InputError("the launch fit needs at least 3 points (M >= 3, or 0 for all points)");
    if (!(o.min_improvement >= 0) || !(o.regularisation_m >= 0) || !(o.robust_m >= 0))
      throw InputError("fit tolerances and weights must be non-negative numbers");
    if (o.max_iterations < 1 || o.max_rounds < 1) throw InputError("iterations and rounds must be at least 1");
    threads_ = o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    env_.air_density = d.air_density;
    env_.air_viscosity = d.air_viscosity;
    env_.gravity = d.gravity;
    topt_.sim = SimOptions{};
    topt_.sim.dt = o.launch.track.sim.dt;
    topt_.sim.integrator = o.launch.track.sim.integrator;
    topt_.gravity = d.gravity;
    topt_.height_offset = o.launch.track.height_offset;
    lopt_ = o.launch;
    lopt_.track = topt_;
    lopt_.robust_m = o.robust_m;
    projected_ = o.launch.points == 0;

    std::map<std::string, int> index;
    for (const auto& [key, g] : d.gliders) {
      GliderCtx c;
      c.key = key;
      c.glider = &g;
      c.mass = mass_properties(g);
      c.body = {c.mass.mass, c.mass.inertia};
      for (const auto& w : g.wings) {
        c.mounts.push_back(w.mount);
        c.wings.push_back(slice_wing(w.outline, o.aero.dz));
      }
      index[key] = static_cast<int>(gliders_.size());
      gliders_.push_back(std::move(c));
    }
    int offset = 0;
    for (const auto& f : d.flights) {
      auto it = index.find(f.glider);
      if (it == index.end()) throw InputError("flight '" + f.name + "' uses unknown glider '" + f.glider + "'");
      FlightCtx fc;
      fc.f = &f;
      fc.glider = it->second;
      fc.points = f.points;
      for (const auto& p : f.points) {
        fc.times.push_back(p.t);
        fc.q.push_back({p.x, p.y});
      }
      fc.offset = offset;
      offset += static_cast<int>(f.points.size());
      gliders_[it->second].flights.push_back(flights_.size());
      try {
        (void)initial_launch_guess(f.points, 6);
      } catch (const InputError& e) {
        throw InputError("flight '" + f.name + "': " + e.what());
      }
      flights_.push_back(std::move(fc));
    }
    points_ = offset;

    // Model structure: scales, validity, prior.
    if (o.start) {
      scales_ = o.start->scales();
      alpha_limit_ = o.start->alpha_limit();
      prior_ = o.start->prior();
    } else {
      scales_ = o.scales;
      alpha_limit_ = deg2rad(o.alpha_limit_deg);
      if (o.use_prior) prior_ = std::make_shared<FlatPlateModel>(o.prior);
    }
    if (!(alpha_limit_ > 0) || alpha_limit_ > kPi / 2) throw InputError("alpha limit must be in (0, 90] deg");
    if (!(scales_.alpha > 0 && scales_.re > 0 && scales_.xi_l > 0 && scales_.xi_t > 0))
      throw InputError("RBF scales must be positive");
    baseline_ = prior_ ? std::static_pointer_cast<const CoefficientModel>(prior_)
                       : std::make_shared<FlatPlateModel>(o.prior);
  }

  FitResult run();

 private:
  // ------------------------------------------------------------ model
  Coefficients reference(const RbfCentre& c) const {
    // Values the regularisation pulls toward: the prior's (or the start values without a prior).
    if (prior_) return prior_->eval({c.alpha, c.re, c.xi_l, c.xi_t});
    return c.value;
  }
  std::vector<RbfCentre> centres_with(const Eigen::VectorXd& u, const std::vector<RbfCentre>& cs,
                                      const std::vector<Coefficients>& ref) const {
    std::vector<RbfCentre> out = cs;
    const double hi[3] = {o_.cd_max, o_.cl_max, o_.cm_max};
    const double lo[3] = {0.0, -o_.cl_max, -o_.cm_max};
    for (std::size_t k = 0; k < cs.size(); ++k)
      for (int i = 0; i < 3; ++i)
        set_coef(out[k].value, i, std::clamp(coef(ref[k], i) + kScale[i] * u(3 * k + i), lo[i], hi[i]));
    return out;
  }
  std::shared_ptr<const RbfModel> model_of(const Eigen::VectorXd& u, const std::vector<RbfCentre>& cs,
                                           const std::vector<Coefficients>& ref) const {
    return std::make_shared<RbfModel>(centres_with(u, cs, ref), scales_, alpha_limit_, prior_);
  }

  // ------------------------------------------------------- simulation
  std::vector<std::shared_ptr<const MountedGlider>> mount_all(const std::shared_ptr<const CoefficientModel>& m,
                                                              int threads) const {
    std::vector<std::shared_ptr<const MountedGlider>> out(gliders_.size());
    parallel_for(static_cast<int>(gliders_.size()), threads, [&](int i) {
      const auto& g = gliders_[i];
      auto aero = std::make_shared<const GliderAero>(*g.glider, m, env_, o_.aero);
      out[i] = std::make_shared<const MountedGlider>(aero, g.mounts, g.mass);
    });
    return out;
  }

  void simulate_all(const std::shared_ptr<const CoefficientModel>& m, const std::vector<LaunchParams>& L,
                    std::vector<Track>& tracks, int threads) {
    tracks.resize(flights_.size());
    parallel_for(static_cast<int>(gliders_.size()), threads, [&](int gi) {
      const auto& g = gliders_[gi];
      auto aero = std::make_shared<const GliderAero>(*g.glider, m, env_, o_.aero);
      const MountedGlider mg(aero, g.mounts, g.mass);
      const QuasiStaticAero qa(mg);
      for (std::size_t fi : g.flights) tracks[fi] = simulate_track(qa, g.body, L[fi], flights_[fi].times, topt_);
    });
    simulations_ += static_cast<long>(flights_.size());
  }

  /// Data residuals (2 per point, Huber-weighted) and the raw sum of squares.
  double data_residuals(const std::vector<Track>& tracks, Eigen::Ref<Eigen::VectorXd> r) const {
    double sse = 0;
    for (std::size_t fi = 0; fi < flights_.size(); ++fi) {
      const auto& fc = flights_[fi];
      for (std::size_t j = 0; j < fc.q.size(); ++j) {
        const double dx = tracks[fi].positions[j].x - fc.q[j].x;
        const double dy = tracks[fi].positions[j].y - fc.q[j].y;
        const double e2 = dx * dx + dy * dy;
        const double w = std::isfinite(e2) ? huber_weight(std::sqrt(e2), o_.robust_m) : 1.0;
        sse += e2;
        const int row = 2 * (fc.offset + static_cast<int>(j));
        r(row) = w * dx;
        r(row + 1) = w * dy;
      }
    }
    return sse;
  }

  int residual_count(std::size_t K) const { return 2 * points_ + 6 * static_cast<int>(K); }

  /// Bayesian information criterion of a fit with K centres and RMS distance rmse.
  double bic(double rmse, int K) const {
    const double n = 2.0 * points_;
    const double p = static_cast<double>(flights_.size()) * (5 + (lopt_.fit_pitch_rate ? 1 : 0)) + 3.0 * K;
    return n * std::log(std::max(rmse * rmse * points_, 1e-300) / n) + p * std::log(n);
  }

  void fill_penalties(const Eigen::VectorXd& u, const std::vector<Coefficients>& ref, Eigen::VectorXd& r) const {
    const double hi[3] = {o_.cd_max, o_.cl_max, o_.cm_max};
    const double lo[3] = {0.0, -o_.cl_max, -o_.cm_max};
    const int K = static_cast<int>(ref.size());
    for (int k = 0; k < K; ++k)
      for (int i = 0; i < 3; ++i) {
        const int p = 3 * k + i;
        r(2 * points_ + p) = o_.regularisation_m * u(p);
        const double v = coef(ref[k], i) + kScale[i] * u(p);
        const double excess = v > hi[i] ? v - hi[i] : (v < lo[i] ? v - lo[i] : 0.0);
        r(2 * points_ + 3 * K + p) = kBoundWeight * excess / kScale[i];
      }
  }

  /// Residuals for values u with the launches L held fixed.
  Eval evaluate(const Eigen::VectorXd& u, const std::vector<RbfCentre>& cs, const std::vector<Coefficients>& ref,
                int threads, const std::vector<LaunchParams>& L, std::vector<Track>* keep = nullptr) {
    Eval e;
    e.r.resize(residual_count(cs.size()));
    std::vector<Track> tracks;
    simulate_all(model_of(u, cs, ref), L, tracks, threads);
    e.sse = data_residuals(tracks, e.r.head(2 * points_));
    fill_penalties(u, ref, e.r);
    if (keep) *keep = std::move(tracks);
    return e;
  }

  /// Variable projection: residuals for values u with every launch re-fitted
  /// (warm start from L, which receives the fitted launches).
  Eval evaluate_projected(const Eigen::VectorXd& u, const std::vector<RbfCentre>& cs,
                          const std::vector<Coefficients>& ref, std::vector<LaunchParams>& L,
                          std::vector<double>& lr) {
    const auto model = model_of(u, cs, ref);
    fit_launches_into(model, L, lr, true);
    return evaluate(u, cs, ref, threads_, L);
  }

  /// Per flight, the weighted residuals' Jacobian with respect to its launch
  /// (forward differences, one flight simulated per column) and the
  /// projection J <- (I - Q Q^T) J of the rows of J belonging to the flight,
  /// Q an orthonormal basis of that Jacobian's columns (Kaufman 1975).
  /// With `G`, also G[f] = (J_L^T J_L)^-1 J_L^T J_f for the first matrix J
  /// (before projection): how the flight's optimal launch moves with the
  /// values to first order, dL = -G du (implicit function theorem), used to
  /// warm-start the launch re-fits of the next evaluations.
  void project_out_launches(const std::shared_ptr<const CoefficientModel>& model, const std::vector<LaunchParams>& L,
                            std::vector<Eigen::MatrixXd*> Js, std::vector<Eigen::MatrixXd>* G = nullptr) {
    if (G) G->assign(flights_.size(), Eigen::MatrixXd());
    const auto mounted = mount_all(model, threads_);
    parallel_for(static_cast<int>(flights_.size()), threads_, [&](int fi) {
      const auto& fc = flights_[fi];
      const auto& g = gliders_[fc.glider];
      const QuasiStaticAero qa(*mounted[fc.glider]);
      const int n = static_cast<int>(fc.q.size());
      auto resid = [&](const LaunchParams& p, Eigen::VectorXd& r) {
        const Track tr = simulate_track(qa, g.body, p, fc.times, topt_);
        for (int j = 0; j < n; ++j) {
          const double dx = tr.positions[j].x - fc.q[j].x, dy = tr.positions[j].y - fc.q[j].y;
          const double w = huber_weight(std::hypot(dx, dy), o_.robust_m);
          r(2 * j) = w * dx;
          r(2 * j + 1) = w * dy;
        }
      };
      const int np = 5 + (lopt_.fit_pitch_rate ? 1 : 0);
      Eigen::VectorXd r0(2 * n), r1(2 * n);
      resid(L[fi], r0);
      Eigen::MatrixXd JL(2 * n, np);
      for (int k = 0; k < np; ++k) {
        LaunchParams p = L[fi];
        double* v[6] = {&p.x, &p.y, &p.speed, &p.climb, &p.pitch, &p.pitch_rate};
        const double h = 1e-6 * std::max(1.0, std::abs(*v[k]));
        *v[k] += h;
        resid(p, r1);
        JL.col(k) = (r1 - r0) / h;
      }
      simulations_ += np + 1;
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(JL);
      const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(2 * n, np);
      if (G && !Js.empty()) {
        const Eigen::MatrixXd R = qr.matrixQR().topRows(np).triangularView<Eigen::Upper>();
        (*G)[fi] = R.triangularView<Eigen::Upper>().solve(Q.transpose() * Js[0]->middleRows(2 * fc.offset, 2 * n));
        if (!(*G)[fi].allFinite()) (*G)[fi].resize(0, 0);  // a degenerate launch Jacobian: no prediction
      }
      for (Eigen::MatrixXd* J : Js) {
        auto rows = J->middleRows(2 * fc.offset, 2 * n);
        rows -= Q * (Q.transpose() * rows);
      }
    });
  }

  // ------------------------------------------------------ launch fits
  void fit_launches_into(const std::shared_ptr<const CoefficientModel>& m, std::vector<LaunchParams>& L,
                         std::vector<double>& lr, bool warm) {
    const auto t = Clock::now();
    const auto mounted = mount_all(m, threads_);
    L.resize(flights_.size());
    lr.resize(flights_.size(), std::numeric_limits<double>::infinity());
    std::atomic<long> sims{0};
    parallel_for(static_cast<int>(flights_.size()), threads_, [&](int fi) {
      const auto& fc = flights_[fi];
      const auto& g = gliders_[fc.glider];
      const QuasiStaticAero qa(*mounted[fc.glider]);
      LaunchFit f;
      if (warm) {
        const double before = lr[fi];
        f = fit_launch(qa, g.body, fc.points, lopt_, &L[fi]);
        // A warm start can sit in a poor local minimum after the model moved:
        // fall back to the multi-start when it fits much worse than the noise
        // and than the same flight did before.
        if (f.rmse_m > 3 * d_.tracking_sigma_m && !(f.rmse_m < 1.5 * before + d_.tracking_sigma_m)) {
          const LaunchFit g2 = fit_launch(qa, g.body, fc.points, lopt_);
          f.evaluations += g2.evaluations;
          if (g2.rmse_m < f.rmse_m) f = g2;
        }
      } else {
        f = fit_launch(qa, g.body, fc.points, lopt_);
      }
      L[fi] = f.launch;
      lr[fi] = f.rmse_m;
      sims += f.evaluations;
    });
    simulations_ += sims;
    launch_seconds_ += since(t);
  }

  void fit_launches(const std::shared_ptr<const CoefficientModel>& m, bool warm) {
    fit_launches_into(m, launches_, launch_rmse_, warm);
  }

  // ------------------------------------------------ coefficient fit (eq. 6)
  struct Problem : Eigen::DenseFunctor<double> {
    Fitter& F;
    const std::vector<RbfCentre>& cs;
    const std::vector<Coefficients>& ref;
    bool projected;  // variable projection (launches re-fitted) or launches fixed
    struct Cached {
      Eigen::VectorXd u;
      Eval e;
      std::vector<LaunchParams> L;
      std::vector<double> lr;
    };
    std::vector<Cached> cache;
    // Linearisation of the launches at the last Jacobian: L*(u) ~ L_J - G (u - u_J).
    Eigen::VectorXd u_J;
    std::vector<LaunchParams> L_J;
    std::vector<Eigen::MatrixXd> G;
    Problem(Fitter& f, const std::vector<RbfCentre>& c, const std::vector<Coefficients>& r, bool proj)
        : DenseFunctor<double>(3 * static_cast<int>(c.size()), f.residual_count(c.size())), F(f), cs(c), ref(r),
          projected(proj) {}
    const Cached& eval(const Eigen::VectorXd& u) {
      for (const auto& c : cache)
        if (c.u.size() == u.size() && c.u == u) return c;
      Cached c;
      c.u = u;
      if (projected) {
        // Warm start from the best point seen so far.
        const Cached* best = nullptr;
        for (const auto& k : cache)
          if (!best || k.e.sse < best->e.sse) best = &k;
        c.L = best ? best->L : F.launches_;
        c.lr = best ? best->lr : F.launch_rmse_;
        if (u_J.size() == u.size() && L_J.size() == c.L.size()) {
          const Eigen::VectorXd du = u - u_J;
          for (std::size_t fi = 0; fi < c.L.size(); ++fi) {
            if (G[fi].rows() == 0) continue;
            const Eigen::VectorXd dL = -G[fi] * du;
            LaunchParams p = L_J[fi];
            double* v[6] = {&p.x, &p.y, &p.speed, &p.climb, &p.pitch, &p.pitch_rate};
            for (int k = 0; k < dL.size(); ++k) *v[k] += dL(k);
            c.L[fi] = p;
          }
        }
        c.e = F.evaluate_projected(u, cs, ref, c.L, c.lr);
      } else {
        c.L = F.launches_;
        c.lr = F.launch_rmse_;
        c.e = F.evaluate(u, cs, ref, F.threads_, c.L);
      }
      if (cache.size() >= 4) {
        // Drop the worst entry (keep the best as the warm start).
        auto worst = std::max_element(cache.begin(), cache.end(),
                                      [](const Cached& a, const Cached& b) { return a.e.sse < b.e.sse; });
        cache.erase(worst);
      }
      cache.push_back(std::move(c));
      return cache.back();
    }
    int operator()(const Eigen::VectorXd& u, Eigen::VectorXd& r) {
      r = eval(u).e.r;
      return r.allFinite() ? 0 : -1;
    }
    int df(const Eigen::VectorXd& u, Eigen::MatrixXd& J) {
      const Cached c = eval(u);
      parallel_for(inputs(), F.threads_, [&](int j) {
        Eigen::VectorXd up = u;
        up(j) += kStep;
        const Eval e = F.evaluate(up, cs, ref, 1, c.L);
        J.col(j) = (e.r - c.e.r) / kStep;
      });
      if (projected) {
        F.project_out_launches(F.model_of(u, cs, ref), c.L, {&J}, &G);
        u_J = u;
        L_J = c.L;
      }
      return 0;
    }
  };

  /// Levenberg-Marquardt on the values u: with the launches re-fitted inside
  /// every evaluation (variable projection) or held fixed (the paper's
  /// alternation). Leaves the launches of the result in launches_. Returns
  /// the number of iterations.
  int fit_values(Eigen::VectorXd& u, const std::vector<RbfCentre>& cs, const std::vector<Coefficients>& ref,
                 int round) {
    const auto t = Clock::now();
    Problem prob(*this, cs, ref, projected_);
    Eigen::LevenbergMarquardt<Problem> lm(prob);
    lm.setMaxfev(10 * o_.max_iterations + 10);
    lm.setFactor(1.0);
    lm.setFtol(1e-4);
    lm.setXtol(1e-5);
    auto status = lm.minimizeInit(u);
    int it = 0;
    while (status != Eigen::LevenbergMarquardtSpace::ImproperInputParameters && it < o_.max_iterations) {
      status = lm.minimizeOneStep(u);
      ++it;
      const double rmse = std::sqrt(prob.eval(u).e.sse / points_);
      report("coefficients", static_cast<int>(cs.size()), round, it, rmse,
             "centres " + std::to_string(cs.size()) + (projected_ ? "" : ", round " + std::to_string(round)) +
                 ", iteration " + std::to_string(it) + ": RMSE " + fmt(rmse) + " m");
      if (status != Eigen::LevenbergMarquardtSpace::Running) break;
    }
    const auto& c = prob.eval(u);
    launches_ = c.L;
    launch_rmse_ = c.lr;
    coefficient_seconds_ += since(t);
    return it;
  }

  // ------------------------------------------------------ insertion
  RbfCentre element_mean(const std::vector<Track>& tracks, int flight_filter = -1, int point = -1,
                         int wing = -1, int glider_filter = -1) const {
    // Area-weighted mean of (|alpha|, Re, xi_l, xi_t) over wing elements, at
    // the tracked times of the selected flights/point/wing/glider.
    double w = 0, a = 0, re = 0, xl = 0, xt = 0;
    for (std::size_t fi = 0; fi < flights_.size(); ++fi) {
      if (flight_filter >= 0 && static_cast<int>(fi) != flight_filter) continue;
      if (glider_filter >= 0 && flights_[fi].glider != glider_filter) continue;
      const auto& g = gliders_[flights_[fi].glider];
      for (std::size_t j = 0; j < tracks[fi].states.size(); ++j) {
        if (point >= 0 && static_cast<int>(j) != point) continue;
        const FlightSample& s = tracks[fi].states[j];
        for (std::size_t wj = 0; wj < g.wings.size(); ++wj) {
          if (wing >= 0 && static_cast<int>(wj) != wing) continue;
          const double alpha = std::abs(s.alpha + deg2rad(g.mounts[wj].angle_deg));
          for (const auto& e : g.wings[wj].elements) {
            w += e.area;
            a += e.area * std::min(alpha, alpha_limit_);
            re += e.area * env_.air_density * s.speed * e.chord / env_.air_viscosity;
            xl += e.area * e.xi_l;
            xt += e.area * e.xi_t;
          }
        }
      }
    }
    RbfCentre c;
    if (w > 0) {
      c.alpha = a / w;
      c.re = re / w;
      c.xi_l = xl / w;
      c.xi_t = xt / w;
    }
    return c;
  }

  double scaled_dist2(const RbfCentre& a, const RbfCentre& b) const {
    auto sq = [](double v) { return v * v; };
    const double rest = sq((a.re - b.re) / scales_.re) + sq((a.xi_l - b.xi_l) / scales_.xi_l) +
                        sq((a.xi_t - b.xi_t) / scales_.xi_t);
    return std::min(sq((a.alpha - b.alpha) / scales_.alpha), sq((a.alpha + b.alpha) / scales_.alpha)) + rest;
  }

  std::vector<RbfCentre> candidates(const std::vector<Track>& tracks, const std::vector<RbfCentre>& cs) const {
    // Two sources, taken in turn: (a) "where the largest error occurs" (the
    // paper): flights by their largest point error; at the worst point, and a
    // third and two thirds of the way to it, each wing's mean element; (b)
    // gliders by their RMS error (with tracking noise a single worst point is
    // mostly noise; a glider's error over all its flights is mostly model
    // error): each wing's mean element over all the glider's tracked states.
    struct Worst {
      double err;
      int flight, point;
    };
    std::vector<Worst> worst;
    std::vector<double> gsum(gliders_.size(), 0.0);
    std::vector<int> gn(gliders_.size(), 0);
    for (std::size_t fi = 0; fi < flights_.size(); ++fi) {
      Worst w{-1, static_cast<int>(fi), 0};
      for (std::size_t j = 0; j < flights_[fi].q.size(); ++j) {
        const double e = norm(tracks[fi].positions[j] - flights_[fi].q[j]);
        if (e > w.err) w = {e, static_cast<int>(fi), static_cast<int>(j)};
        gsum[flights_[fi].glider] += e * e;
        ++gn[flights_[fi].glider];
      }
      worst.push_back(w);
    }
    std::sort(worst.begin(), worst.end(), [](const Worst& a, const Worst& b) { return a.err > b.err; });
    std::vector<int> gorder(gliders_.size());
    for (std::size_t i = 0; i < gorder.size(); ++i) gorder[i] = static_cast<int>(i);
    std::sort(gorder.begin(), gorder.end(), [&](int a, int b) {
      return gsum[a] / std::max(gn[a], 1) > gsum[b] / std::max(gn[b], 1);
    });
    std::vector<RbfCentre> out;
    auto fresh = [&](const RbfCentre& c) {
      for (const auto& e : cs)
        if (scaled_dist2(c, e) < 0.25) return false;
      for (const auto& e : out)
        if (scaled_dist2(c, e) < 0.25) return false;
      return c.re > 0;
    };
    std::vector<RbfCentre> from_points, from_gliders;
    for (const auto& w : worst) {
      const auto& g = gliders_[flights_[w.flight].glider];
      for (int p : {w.point, (2 * w.point) / 3, w.point / 3})
        for (std::size_t wj = 0; wj < g.wings.size(); ++wj)
          from_points.push_back(element_mean(tracks, w.flight, p, static_cast<int>(wj)));
      if (static_cast<int>(from_points.size()) > 4 * o_.candidates) break;
    }
    for (int gi : gorder)
      for (std::size_t wj = 0; wj < gliders_[gi].wings.size(); ++wj)
        from_gliders.push_back(element_mean(tracks, -1, -1, static_cast<int>(wj), gi));
    std::size_t ia = 0, ib = 0;
    while (static_cast<int>(out.size()) < o_.candidates && (ia < from_points.size() || ib < from_gliders.size())) {
      for (int k = 0; k < 2; ++k) {
        auto& src = k == 0 ? from_points : from_gliders;
        auto& i = k == 0 ? ia : ib;
        while (i < src.size()) {
          const RbfCentre c = src[i++];
          if (fresh(c)) {
            out.push_back(c);
            break;
          }
        }
        if (static_cast<int>(out.size()) >= o_.candidates) break;
      }
    }
    return out;
  }

  void report(const std::string& stage, int centres, int round, int iteration, double rmse, const std::string& msg) {
    if (!cb_) return;
    FitProgress p;
    p.stage = stage;
    p.centres = centres;
    p.round = round;
    p.iteration = iteration;
    p.rmse_m = rmse;
    p.elapsed_s = since(t0_);
    p.message = msg;
    cb_(p);
  }

  /// Fits values (and launches) for a fixed set of centres; returns the RMSE.
  double fit_stage(Eigen::VectorXd& u, const std::vector<RbfCentre>& cs, const std::vector<Coefficients>& ref,
                   FitStage& st) {
    if (projected_) {
      st.iterations += fit_values(u, cs, ref, 1);
      return std::sqrt(evaluate(u, cs, ref, threads_, launches_).sse / points_);
    }
    // The paper's alternation. Its launch fit (eq. 5) minimises the error of
    // the first M points only, so a round can raise the total error: the
    // best round is kept.
    double prev = std::numeric_limits<double>::infinity();
    Eigen::VectorXd prev_u = u;
    std::vector<LaunchParams> prev_L = launches_;
    std::vector<double> prev_lr = launch_rmse_;
    for (int round = 1; round <= o_.max_rounds; ++round) {
      if (round > 1) {
        fit_launches(model_of(u, cs, ref), true);
        report("launches", static_cast<int>(cs.size()), round, 0, 0,
               "centres " + std::to_string(cs.size()) + ", round " + std::to_string(round) + ": launches refitted");
      }
      st.iterations += fit_values(u, cs, ref, round);
      const double rmse = std::sqrt(evaluate(u, cs, ref, threads_, launches_).sse / points_);
      if (rmse > prev) {  // worse than the previous round: undo it
        u = prev_u;
        launches_ = prev_L;
        launch_rmse_ = prev_lr;
        break;
      }
      const bool small = prev - rmse < o_.round_tolerance * prev;
      prev = rmse;
      prev_u = u;
      prev_L = launches_;
      prev_lr = launch_rmse_;
      if (small) break;
    }
    return prev;
  }

  const Dataset& d_;
  FitOptions o_;
  FitCallback cb_;
  Clock::time_point t0_;
  int threads_ = 1;
  Environment env_;
  TrackOptions topt_;
  LaunchFitOptions lopt_;
  std::vector<GliderCtx> gliders_;
  std::vector<FlightCtx> flights_;
  int points_ = 0;
  RbfScales scales_;
  double alpha_limit_ = 0;
  std::shared_ptr<const FlatPlateModel> prior_;
  std::shared_ptr<const CoefficientModel> baseline_;
  bool projected_ = true;
  std::vector<LaunchParams> launches_;
  std::vector<double> launch_rmse_;
  std::atomic<long> simulations_{0};
  double launch_seconds_ = 0, coefficient_seconds_ = 0, insertion_seconds_ = 0;
};

FitResult Fitter::run() {
  FitResult res;
  res.threads = threads_;
  res.points = points_;

  // Stage 0: launches of the starting model (the prior, or the start model).
  const std::shared_ptr<const CoefficientModel> m0 =
      o_.start ? std::static_pointer_cast<const CoefficientModel>(o_.start) : baseline_;
  report("launches", 0, 0, 0, 0, "fitting the launches of " + std::to_string(flights_.size()) + " flights");
  fit_launches(m0, false);
  std::vector<Track> tracks;
  simulate_all(m0, launches_, tracks, threads_);
  {
    Eigen::VectorXd dummy(2 * points_);
    res.prior_rmse_m = std::sqrt(data_residuals(tracks, dummy) / points_);
  }
  FitStage s0;
  s0.centres = o_.start ? static_cast<int>(o_.start->centres().size()) : 0;
  s0.rmse_m = res.prior_rmse_m;
  s0.bic = bic(s0.rmse_m, s0.centres);
  s0.seconds = since(t0_);
  s0.simulations = static_cast<int>(simulations_);
  if (!o_.start) res.history.push_back(s0);
  report("stage", s0.centres, 0, 0, res.prior_rmse_m,
         std::string(o_.start ? "start model" : "prior (flat-plate element)") + " with fitted launches: RMSE " +
             fmt(res.prior_rmse_m) + " m over " + std::to_string(points_) + " points");

  // Initial centres.
  std::vector<RbfCentre> cs;
  if (o_.start) {
    cs = o_.start->centres();
  } else {
    RbfCentre c = element_mean(tracks);
    c.value = baseline_->eval({c.alpha, c.re, c.xi_l, c.xi_t});
    cs.push_back(c);
  }
  std::vector<Coefficients> ref;
  for (const auto& c : cs) ref.push_back(reference(c));
  Eigen::VectorXd u(3 * cs.size());
  for (std::size_t k = 0; k < cs.size(); ++k)
    for (int i = 0; i < 3; ++i) u(3 * k + i) = (coef(cs[k].value, i) - coef(ref[k], i)) / kScale[i];

  FitStage st;
  st.centres = static_cast<int>(cs.size());
  st.has_added = !o_.start;
  if (!o_.start) st.added = cs[0];
  auto t_stage = Clock::now();
  long sims0 = simulations_;
  const Eigen::VectorXd u0 = u;
  const std::vector<LaunchParams> L0 = launches_;
  const std::vector<double> lr0 = launch_rmse_;
  double rmse = fit_stage(u, cs, ref, st);
  st.rmse_m = rmse;
  st.bic = bic(rmse, st.centres);
  st.seconds = since(t_stage);
  st.simulations = static_cast<int>(simulations_ - sims0);
  // Without a start model the first centre is judged against the prior alone.
  bool prior_only = false;
  if (!o_.start && (!(rmse < res.prior_rmse_m) || (o_.information_criterion && !(st.bic < s0.bic)))) {
    st.accepted = false;
    prior_only = true;
  }
  res.history.push_back(st);
  report("stage", st.centres, 0, 0, rmse,
         std::to_string(cs.size()) + " centre(s): RMSE " + fmt(rmse) + " m" +
             (prior_only ? " (dropped: no better than the prior once its three values are paid for)" : ""));

  // Accepted state.
  if (prior_only) {  // the model is the prior: one centre valued as the prior
    u = u0;
    launches_ = L0;
    launch_rmse_ = lr0;
    rmse = res.prior_rmse_m;
  }
  std::vector<RbfCentre> best_cs = cs;
  std::vector<Coefficients> best_ref = ref;
  Eigen::VectorXd best_u = u;
  std::vector<LaunchParams> best_L = launches_;
  std::vector<double> best_lr = launch_rmse_;
  double best_rmse = rmse;
  const std::string reached_max = "reached the maximum number of centres (" + std::to_string(o_.max_centres) + ")";
  res.stop_reason = reached_max;
  if (prior_only)
    res.stop_reason = "the error stopped falling: one centre does not fit the flights better than the prior by "
                      "more than its three values fit noise (BIC); the model equals the prior";

  while (!prior_only && static_cast<int>(best_cs.size()) < o_.max_centres) {
    // Greedy insertion: candidates where the error is largest, scored by the
    // Gauss-Newton decrease their three values alone would give.
    const auto t_ins = Clock::now();
    t_stage = t_ins;
    sims0 = simulations_;
    launches_ = best_L;
    std::vector<Track> tr;
    const Eval base = evaluate(best_u, best_cs, best_ref, threads_, launches_, &tr);
    const auto current = model_of(best_u, best_cs, best_ref);
    const std::vector<RbfCentre> cand = candidates(tr, best_cs);
    if (cand.empty()) {
      res.stop_reason = "no new centre location away from the existing centres";
      break;
    }
    report("insert", static_cast<int>(best_cs.size()) + 1, 0, 0, best_rmse,
           "scoring " + std::to_string(cand.size()) + " candidate centres");
    const int K = static_cast<int>(best_cs.size());
    const int nd = 2 * points_;
    std::vector<Eigen::MatrixXd> J(cand.size(), Eigen::MatrixXd(nd, 3));
    std::vector<std::vector<RbfCentre>> ccs(cand.size());
    std::vector<std::vector<Coefficients>> crefs(cand.size());
    std::vector<Eigen::VectorXd> cus(cand.size());
    for (std::size_t c = 0; c < cand.size(); ++c) {
      RbfCentre nc = cand[c];
      nc.value = current->eval({nc.alpha, nc.re, nc.xi_l, nc.xi_t});
      ccs[c] = best_cs;
      ccs[c].push_back(nc);
      crefs[c] = best_ref;
      crefs[c].push_back(reference(nc));
      cus[c].resize(3 * (K + 1));
      cus[c].head(3 * K) = best_u;
      for (int i = 0; i < 3; ++i) cus[c](3 * K + i) = (coef(nc.value, i) - coef(crefs[c].back(), i)) / kScale[i];
    }
    parallel_for(static_cast<int>(3 * cand.size()), threads_, [&](int job) {
      const int c = job / 3, i = job % 3;
      Eigen::VectorXd up = cus[c];
      up(3 * K + i) += kStep;
      const Eval e = evaluate(up, ccs[c], crefs[c], 1, launches_);
      J[c].col(i) = (e.r.head(nd) - base.r.head(nd)) / kStep;
    });
    if (projected_) {
      std::vector<Eigen::MatrixXd*> Js;
      for (auto& m : J) Js.push_back(&m);
      project_out_launches(current, launches_, Js);
    }
    const double lam2 = o_.regularisation_m * o_.regularisation_m + 1e-12;
    // The candidates by their scored gain, largest first; among equal gains
    // the first scored (the greedy rule takes ranked[0]).
    std::vector<std::pair<double, int>> ranked;  // (gain, candidate)
    for (std::size_t c = 0; c < cand.size(); ++c) {
      const Eigen::Vector3d g = J[c].transpose() * base.r.head(nd);
      const Eigen::Matrix3d H = J[c].transpose() * J[c] + lam2 * Eigen::Matrix3d::Identity();
      const double gain = g.dot(H.ldlt().solve(g));
      if (std::isfinite(gain)) ranked.push_back({gain, static_cast<int>(c)});
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    insertion_seconds_ += since(t_ins);
    if (ranked.empty()) {
      res.stop_reason = "no candidate centre can lower the error";
      break;
    }
    // The best-scored candidate; with insertion_tries, the next-best in turn
    // while the fit stays over twice the tracking noise.
    bool accepted_any = false;
    const int tries = std::min(std::max(1, o_.insertion_tries), static_cast<int>(ranked.size()));
    for (int attempt = 0; attempt < tries && !accepted_any; ++attempt) {
      if (attempt > 0) {
        if (!(d_.tracking_sigma_m > 0 && best_rmse > 2 * d_.tracking_sigma_m)) break;
        launches_ = best_L;  // from the accepted state
        launch_rmse_ = best_lr;
        sims0 = simulations_;
        t_stage = Clock::now();
      }
      const auto [best_gain, bestc] = ranked[attempt];
      cs = ccs[bestc];
      ref = crefs[bestc];
      u = cus[bestc];
      FitStage ns;
      ns.centres = K + 1;
      ns.has_added = true;
      ns.added = cs.back();
      ns.predicted_gain = best_gain;
      report("insert", K + 1, 0, 0, best_rmse,
             "new centre at alpha " + fmt(rad2deg(ns.added.alpha), 3) + " deg, Re " + fmt(ns.added.re, 3) +
                 ", xi_l " + fmt(rad2deg(ns.added.xi_l), 3) + " deg, xi_t " + fmt(rad2deg(ns.added.xi_t), 3) + " deg");
      rmse = fit_stage(u, cs, ref, ns);
      ns.rmse_m = rmse;
      ns.seconds = since(t_stage);
      ns.simulations = static_cast<int>(simulations_ - sims0);
      ns.bic = bic(rmse, K + 1);
      const double best_bic = bic(best_rmse, K);
      std::string why;
      if (!(rmse < best_rmse)) why = "did not lower the RMSE";
      else if (o_.information_criterion && !(ns.bic < best_bic))
        why = "lowered the RMSE by " + fmt(100 * (1 - rmse / best_rmse), 2) +
              " %, less than three more parameters gain on noise alone (BIC " + fmt(ns.bic, 6) + " >= " +
              fmt(best_bic, 6) + ")";
      else if (!(rmse < best_rmse * (1 - o_.min_improvement)))
        why = "lowered the RMSE by less than " + fmt(100 * o_.min_improvement, 3) + " %";
      ns.accepted = why.empty();
      res.history.push_back(ns);
      report("stage", K + 1, 0, 0, rmse,
             std::to_string(K + 1) + " centres: RMSE " + fmt(rmse) + " m" + (ns.accepted ? "" : " (dropped: it " + why + ")"));
      if (!ns.accepted) {
        res.stop_reason = "the error stopped falling: centre " + std::to_string(K + 1) + " " + why;
        continue;
      }
      accepted_any = true;
      best_cs = cs;
      best_ref = ref;
      best_u = u;
      best_L = launches_;
      best_lr = launch_rmse_;
      best_rmse = rmse;
    }
    if (!accepted_any) break;
    res.stop_reason = reached_max;  // a dropped try before the accepted one set another reason
  }

  // Final state: the accepted model and its launches.
  launches_ = best_L;
  launch_rmse_ = best_lr;
  res.model = model_of(best_u, best_cs, best_ref);
  std::vector<Track> fin;
  simulate_all(res.model, launches_, fin, threads_);
  Eigen::VectorXd dummy(2 * points_);
  res.rmse_m = std::sqrt(data_residuals(fin, dummy) / points_);
  for (std::size_t fi = 0; fi < flights_.size(); ++fi) {
    const auto& fc = flights_[fi];
    FlightFitResult ff;
    ff.flight = fc.f->name;
    ff.glider = fc.f->glider;
    ff.points = static_cast<int>(fc.q.size());
    ff.launch = launches_[fi];
    double s = 0;
    for (std::size_t j = 0; j < fc.q.size(); ++j) {
      const double e = norm(fin[fi].positions[j] - fc.q[j]);
      s += e * e;
      ff.max_error_m = std::max(ff.max_error_m, e);
    }
    ff.rmse_m = std::sqrt(s / fc.q.size());
    ff.launch_rmse_m = launch_rmse_[fi];
    ff.max_alpha = fin[fi].max_alpha;
    ff.left_model_range = fin[fi].left_model_range;
    res.flights.push_back(ff);
  }
  res.seconds = since(t0_);
  res.launch_seconds = launch_seconds_;
  res.coefficient_seconds = coefficient_seconds_;
  res.insertion_seconds = insertion_seconds_;
  res.simulations = simulations_;
  report("done", static_cast<int>(best_cs.size()), 0, 0, res.rmse_m,
         "fitted " + std::to_string(best_cs.size()) + " centres: RMSE " + fmt(res.rmse_m) + " m (prior " +
             fmt(res.prior_rmse_m) + " m) in " + fmt(res.seconds, 3) + " s; " + res.stop_reason);
  return res;
}

}  // namespace

FitResult fit_coefficients(const Dataset& d, const FitOptions& opt, const FitCallback& progress) {
  Fitter f(d, opt, progress);
  return f.run();
}

}  // namespace pteromys
