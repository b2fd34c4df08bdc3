// Fitting core of the diagnosis (diagnose_fit.hpp): launches, effect
// strengths, per-glider trims and (optionally) RBF centre values, by
// Levenberg-Marquardt with variable projection of the launches.
#include "pteromys/diagnose_fit.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <thread>
#include <cstdio>
#include <cstdlib>

#include "pteromys/mass.hpp"

#include "parallel.hpp"

namespace pteromys {
namespace {

using detail::parallel_for;

constexpr double kCoefScale[3] = {0.02, 0.1, 0.02};  // cd, cl, cm (as fit.cpp)
constexpr double kHeightOffset = 1000.0;              // flights are simulated this high (no ground cut)
constexpr int kLaunchParams = 5;                      // x, y, speed, climb, pitch (+ pitch rate per flight)

/// `rbf` with its centre values `values0` moved by `u` (3 per centre: cd, cl,
/// cm in kCoefScale units; drag kept >= 0).
std::shared_ptr<const CoefficientModel> moved_values(const RbfModel& rbf, std::vector<Coefficients> v,
                                                     const std::vector<double>& u) {
  for (std::size_t k = 0; k < v.size(); ++k) {
    v[k].cd = std::max(0.0, v[k].cd + kCoefScale[0] * u[3 * k]);
    v[k].cl += kCoefScale[1] * u[3 * k + 1];
    v[k].cm += kCoefScale[2] * u[3 * k + 2];
  }
  return rbf.with_values(v);
}

/// Fitted values of one launch: 5, or 6 when launch_rotation is a launch parameter.
int launch_count(const EffectValues& ev) { return ev.launch_rotation_per_flight ? kLaunchParams + 1 : kLaunchParams; }

double* launch_value(LaunchParams& p, int k) {
  switch (k) {
    case 0: return &p.x;
    case 1: return &p.y;
    case 2: return &p.speed;
    case 3: return &p.climb;
    case 4: return &p.pitch;
    default: return &p.pitch_rate;
  }
}

}  // namespace

// ------------------------------------------------------------ model setup

struct DiagnosisData::Impl {
  Environment env;
  /// Everything needed to simulate the flights of the used gliders under one model.
  struct Setup {
    EffectValues ev;
    std::vector<std::shared_ptr<const GliderAero>> aero;
    std::vector<std::unique_ptr<MountedGlider>> mg;
    std::vector<std::unique_ptr<EffectAero>> ea;
    TrackOptions topt;
  };
};

namespace {

using Setup = DiagnosisData::Impl::Setup;

struct FitContext {
  const DiagnosisData& D;
  const DiagnosisData::Impl& impl;
  std::vector<int> flights;
  std::vector<char> used;  // per glider
  std::shared_ptr<const RbfModel> rbf;  // for coefficient parameters
  std::vector<Coefficients> values0;    // centre values of rbf
  mutable std::atomic<long> sims{0}, refines{0}, refine_iterations{0};
  /// Simulations spent in multi-started launch fits, with the residuals and
  /// refinement that follow each: by trials' fallbacks (how many, how many
  /// kept) and by refreshes. With the environment
  /// variable PTEROMYS_FIT_STATS set, every fit prints them to stderr (where
  /// a slow diagnosis spends its time; docs/diagnosis.md, Speed).
  mutable std::atomic<long> fallback_sims{0}, refresh_sims{0}, fallbacks{0}, fallbacks_helped{0};

  FitContext(const DiagnosisData& d, const DiagnosisData::Impl& i, const std::vector<int>& f)
      : D(d), impl(i), flights(f), used(d.gliders().size(), 0) {
    for (int fi : flights) used[d.glider_of(fi)] = 1;
  }

  /// When any of `free` is a centre value: points this context at `m`'s RBF
  /// model and returns the centre-value offsets u, all 0 (3 per centre);
  /// otherwise an empty u.
  std::vector<double> centre_offsets(const DiagModel& m, const std::vector<FreeParam>& free) {
    bool coef = false;
    for (const auto& p : free) coef = coef || p.kind == FreeParam::Coefficient;
    if (!coef) return {};
    rbf = std::dynamic_pointer_cast<const RbfModel>(m.coefficients);
    if (!rbf) throw InputError("coefficient parameters need an RBF model");
    values0.clear();
    for (const auto& c : rbf->centres()) values0.push_back(c.value);
    std::vector<double> u(3 * values0.size(), 0.0);
    for (const auto& p : free)
      if (p.kind == FreeParam::Coefficient && (p.index < 0 || p.index >= static_cast<int>(u.size())))
        throw InputError("coefficient parameter out of range");
    return u;
  }

  std::shared_ptr<const CoefficientModel> coefficients_of(const DiagModel& m, const std::vector<double>& u) const {
    if (!rbf || u.empty()) return m.coefficients;
    return moved_values(*rbf, values0, u);
  }

  std::vector<std::shared_ptr<const GliderAero>> tables(const std::shared_ptr<const CoefficientModel>& m) const {
    std::vector<std::shared_ptr<const GliderAero>> out(D.gliders().size());
    std::vector<int> idx;
    for (std::size_t g = 0; g < used.size(); ++g)
      if (used[g]) idx.push_back(static_cast<int>(g));
    parallel_for(static_cast<int>(idx.size()), D.threads(), [&](int k) {
      const int g = idx[k];
      out[g] = std::make_shared<const GliderAero>(*D.gliders()[g].glider, m, impl.env, D.options().aero);
    });
    return out;
  }

  std::unique_ptr<Setup> setup(const DiagModel& m, const std::vector<std::shared_ptr<const GliderAero>>& aero) const {
    auto s = std::make_unique<Setup>();
    s->ev = m.effects;
    s->aero = aero;
    s->mg.resize(D.gliders().size());
    s->ea.resize(D.gliders().size());
    for (std::size_t g = 0; g < used.size(); ++g) {
      if (!used[g]) continue;
      const auto& G = D.gliders()[g];
      std::vector<Mount> mounts;
      for (const auto& w : G.glider->wings) mounts.push_back(w.mount);
      if (G.features.trim_wing >= 0 && g < m.trim.size())
        mounts[G.features.trim_wing].angle_deg += rad2deg(m.trim[g]);
      MassProperties mp;
      mp.mass = G.features.mass;
      mp.cg = G.features.cg;
      mp.inertia = G.features.inertia;
      s->mg[g] = std::make_unique<MountedGlider>(aero[g], mounts, mp);
      s->ea[g] = std::make_unique<EffectAero>(*s->mg[g], G.features, m.effects,
                                              kHeightOffset + D.options().ground_y);
    }
    s->topt.sim.dt = D.options().dt;
    s->topt.sim.wind = {m.effects.wind, 0.0};
    s->topt.gravity = D.dataset().gravity;
    s->topt.height_offset = kHeightOffset;
    s->topt.continue_outside_range = true;
    return s;
  }

  std::vector<TrackedPoint> world_points(const Setup& s, int fi) const {
    std::vector<TrackedPoint> p = D.dataset().flights[fi].points;
    if (s.ev.camera_scale != 0 || s.ev.camera_roll != 0)
      for (auto& q : p) {
        const Vec2 w = camera_to_world({q.x, q.y}, s.ev);
        q.x = w.x;
        q.y = w.y;
      }
    return p;
  }

  /// Residuals (camera frame) of flight fi with launch L; optionally the track.
  /// `also`: a counter the simulation is added to besides `sims`.
  void residuals(const Setup& s, int fi, LaunchParams L, Eigen::VectorXd& r, Track* keep = nullptr,
                 std::atomic<long>* also = nullptr) const {
    const auto& f = D.dataset().flights[fi];
    const int g = D.glider_of(fi);
    std::vector<double> times;
    times.reserve(f.points.size());
    for (const auto& q : f.points) times.push_back(q.t);
    if (!s.ev.launch_rotation_per_flight) L.pitch_rate = s.ev.launch_rotation;
    Track tr = simulate_track(*s.ea[g], D.gliders()[g].body, L, times, s.topt);
    ++sims;
    if (also) ++*also;
    r.resize(2 * f.points.size());
    for (std::size_t i = 0; i < f.points.size(); ++i) {
      const Vec2 p = world_to_camera(tr.positions[i], s.ev);
      r(2 * i) = p.x - f.points[i].x;
      r(2 * i + 1) = p.y - f.points[i].y;
    }
    if (!r.allFinite()) r.setConstant(1e3);  // a diverged simulation: a large, finite misfit
    if (keep) *keep = std::move(tr);
  }

  /// Forward-difference Jacobian of flight fi's residuals over the first nl
  /// launch values at launch L, whose residuals are r0 (step 1e-6 relative,
  /// at least 1e-6 absolute). `also` as residuals().
  Eigen::MatrixXd launch_jacobian(const Setup& s, int fi, const LaunchParams& L, const Eigen::VectorXd& r0, int nl,
                                  std::atomic<long>* also = nullptr) const {
    Eigen::MatrixXd J(r0.size(), nl);
    Eigen::VectorXd r1;
    for (int k = 0; k < nl; ++k) {
      LaunchParams p = L;
      double* v = launch_value(p, k);
      const double h = 1e-6 * std::max(1.0, std::abs(*v));
      *v += h;
      residuals(s, fi, p, r1, nullptr, also);
      J.col(k) = (r1 - r0) / h;
    }
    return J;
  }

  /// Gauss-Newton refinement of a launch from a warm start (finite-difference
  /// Jacobian, Levenberg damping): a few iterations suffice when the start is
  /// the linear prediction of the shared parameters' step.
  /// `also`: a counter its simulations are added to besides `sims`.
  void refine_launch(const Setup& s, int fi, LaunchParams& L, Eigen::VectorXd& r, int iterations,
                     std::atomic<long>* also = nullptr) const {
    residuals(s, fi, L, r, nullptr, also);
    ++refines;
    const double s2 = D.dataset().tracking_sigma_m * D.dataset().tracking_sigma_m;
    double lambda = 1e-4;
    Eigen::VectorXd r1;
    const int nl = launch_count(s.ev);
    for (int it = 0; it < iterations; ++it) {
      ++refine_iterations;
      const Eigen::MatrixXd J = launch_jacobian(s, fi, L, r, nl, also);
      const Eigen::MatrixXd H = J.transpose() * J;
      const Eigen::VectorXd g = J.transpose() * r;
      bool better = false;
      for (int t = 0; t < 4 && !better; ++t) {
        Eigen::MatrixXd A = H;
        for (int k = 0; k < nl; ++k) A(k, k) += lambda * H(k, k) + 1e-15;
        const Eigen::VectorXd d = -A.ldlt().solve(g);
        if (!d.allFinite()) break;
        LaunchParams p = L;
        for (int k = 0; k < nl; ++k) *launch_value(p, k) += d(k);
        p.speed = std::max(p.speed, 0.05);
        residuals(s, fi, p, r1, nullptr, also);
        if (r1.squaredNorm() < r.squaredNorm()) {
          const double gain = r.squaredNorm() - r1.squaredNorm();
          L = p;
          r = r1;
          better = true;
          lambda = std::max(lambda / 10, 1e-9);
          if (gain < 1e-3 * s2) return;  // converged: far below what matters against the noise
        } else {
          lambda *= 10;
        }
      }
      if (!better) return;
    }
  }

  /// Multi-start launch fit (eq. 5 from pitch = path + {-3, 1, 5} deg).
  /// `evaluations`: if given, the simulations it ran are added.
  LaunchParams cold_launch(const Setup& s, int fi, std::atomic<long>* evaluations = nullptr) const {
    const int g = D.glider_of(fi);
    const auto pts = world_points(s, fi);
    LaunchFitOptions lo;
    lo.points = 0;
    lo.fit_pitch = true;
    lo.fit_pitch_rate = s.ev.launch_rotation_per_flight;
    lo.robust_m = 0;
    lo.track = s.topt;
    lo.max_evaluations = 400;
    LaunchParams guess;
    try {
      guess = initial_launch_guess(pts, std::min<int>(6, pts.size()));
    } catch (const InputError&) {
      // A camera candidate's trial roll and scale can turn the first points
      // backwards (an outlier among them): start from the recorded points,
      // which were checked to move along +x, and let the fit move it.
      const auto& rec = D.dataset().flights[fi].points;
      guess = initial_launch_guess(rec, std::min<int>(6, rec.size()));
      const Vec2 w = camera_to_world({guess.x, guess.y}, s.ev);  // its place as this trial sees it
      guess.x = w.x;
      guess.y = w.y;
    }
    guess.pitch_rate = s.ev.launch_rotation;
    LaunchFit best;
    best.rmse_m = std::numeric_limits<double>::infinity();
    for (double a : {-3.0, 1.0, 5.0}) {
      LaunchParams st = guess;
      st.pitch = guess.climb + deg2rad(a);
      const LaunchFit lf = fit_launch(*s.ea[g], D.gliders()[g].body, pts, lo, &st);
      sims += lf.evaluations;
      if (evaluations) *evaluations += lf.evaluations;
      if (lf.rmse_m < best.rmse_m) best = lf;
    }
    if (!s.ev.launch_rotation_per_flight) best.launch.pitch_rate = s.ev.launch_rotation;
    return best.launch;
  }

  /// Launch of flight fi: refined from a warm start, or multi-started; with
  /// `fallback`, a warm start that ends worse than `previous_sse` (and worse
  /// than tracking noise) is multi-started as well and the better kept.
  void fit_launch_of(const Setup& s, int fi, LaunchParams& L, bool warm, double previous_sse, bool fallback,
                     Eigen::VectorXd& r) const {
    const double s2 = D.dataset().tracking_sigma_m * D.dataset().tracking_sigma_m;
    if (warm) {
      if (!s.ev.launch_rotation_per_flight) L.pitch_rate = s.ev.launch_rotation;
      refine_launch(s, fi, L, r, 10);
      const double expect = s2 * std::max(1.0, static_cast<double>(r.size()) - 5.0);
      if (fallback && r.squaredNorm() > 1.5 * expect && !(r.squaredNorm() <= 1.02 * previous_sse)) {
        LaunchParams c = cold_launch(s, fi, &fallback_sims);
        Eigen::VectorXd rc;
        residuals(s, fi, c, rc, nullptr, &fallback_sims);
        ++fallbacks;
        if (rc.squaredNorm() < r.squaredNorm()) {
          ++fallbacks_helped;
          L = c;
          r = rc;
        }
      }
    } else {
      L = cold_launch(s, fi);
      refine_launch(s, fi, L, r, 1);
    }
  }

  /// Launch fits of every flight; residuals in R. Returns the SSE.
  double fit_all(const Setup& s, std::vector<LaunchParams>& L, std::vector<double>& lr, bool warm,
                 std::vector<Eigen::VectorXd>& R, bool fallback = true) const {
    const int n = static_cast<int>(flights.size());
    L.resize(n);
    lr.resize(n, std::numeric_limits<double>::infinity());
    R.resize(n);
    parallel_for(n, D.threads(), [&](int k) {
      fit_launch_of(s, flights[k], L[k], warm, lr[k], fallback, R[k]);
      lr[k] = R[k].squaredNorm();
    });
    double sse = 0;
    for (const auto& r : R) sse += r.squaredNorm();
    return sse;
  }

  /// Flights that fit much worse than tracking noise allows (squared error
  /// above twice its expectation sigma^2 (2 n - 5)) may sit in a poor basin
  /// of their launch fit after the model moved: multi-start them afresh and
  /// keep what fits better. Returns the new SSE.
  double refresh(const Setup& s, std::vector<LaunchParams>& L, std::vector<double>& lr,
                 std::vector<Eigen::VectorXd>& R) const {
    const double s2 = D.dataset().tracking_sigma_m * D.dataset().tracking_sigma_m;
    const int n = static_cast<int>(flights.size());
    parallel_for(n, D.threads(), [&](int k) {
      const double expect = s2 * std::max(1.0, static_cast<double>(R[k].size()) - 5.0);
      if (!(R[k].squaredNorm() > 2 * expect)) return;
      LaunchParams c = cold_launch(s, flights[k], &refresh_sims);
      Eigen::VectorXd r;
      refine_launch(s, flights[k], c, r, 1, &refresh_sims);
      if (r.squaredNorm() < R[k].squaredNorm()) {
        L[k] = c;
        lr[k] = r.squaredNorm();
        R[k] = r;
      }
    });
    double sse = 0;
    for (const auto& r : R) sse += r.squaredNorm();
    return sse;
  }
};

}  // namespace

// ------------------------------------------------------------ DiagnosisData

DiagnosisData::DiagnosisData(const Dataset& d, const DiagFitOptions& o) : d_(d), o_(o) {
  if (d.flights.empty()) throw InputError("the dataset has no flights");
  const auto problems = dataset_problems(d);
  if (!problems.empty()) throw InputError("invalid dataset: " + problems.front());
  if (!(d.tracking_sigma_m > 0)) throw InputError("the dataset's tracking_sigma_m must be positive");
  check_time_step(o.dt, "the simulation step");
  if (!std::isfinite(o.ground_y)) throw InputError("the ground height must be a finite number");
  threads_ = o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  impl_ = std::make_shared<Impl>();
  impl_->env.air_density = d.air_density;
  impl_->env.air_viscosity = d.air_viscosity;
  impl_->env.gravity = d.gravity;
  std::map<std::string, int> index;
  for (const auto& [key, g] : d.gliders) {
    DiagGlider G;
    G.key = key;
    G.glider = &g;
    G.features = glider_features(g, o.aero.dz, d.gravity);
    if (G.features.wings.size() > 8) throw InputError("glider '" + key + "' has more than 8 wings");
    G.body = {G.features.mass, G.features.inertia};
    index[key] = static_cast<int>(gliders_.size());
    gliders_.push_back(std::move(G));
  }
  for (std::size_t i = 0; i < d.flights.size(); ++i) {
    const auto& f = d.flights[i];
    auto it = index.find(f.glider);
    if (it == index.end()) throw InputError("flight '" + f.name + "' uses unknown glider '" + f.glider + "'");
    try {
      (void)initial_launch_guess(f.points, 6);
    } catch (const InputError& e) {
      throw InputError("flight '" + f.name + "': " + e.what());
    }
    flight_glider_.push_back(it->second);
    gliders_[it->second].flights.push_back(static_cast<int>(i));
  }
}

double DiagnosisData::scale(const FreeParam& p) const {
  switch (p.kind) {
    case FreeParam::EffectParam: return effect_spec(p.effect).parameters.at(p.index).scale;
    case FreeParam::Trim: return deg2rad(1.0);
    case FreeParam::Coefficient: return kCoefScale[p.index % 3];
  }
  return 1.0;
}

namespace {

/// Values of the free parameters (in their natural units) in a model.
double get_param(const DiagModel& m, const FreeParam& p, const std::vector<double>& u) {
  switch (p.kind) {
    case FreeParam::EffectParam: return m.effects.at(p.effect, p.index);
    case FreeParam::Trim: return p.index < static_cast<int>(m.trim.size()) ? m.trim[p.index] : 0.0;
    case FreeParam::Coefficient: return u.empty() ? 0.0 : u[p.index];
  }
  return 0;
}

void set_param(DiagModel& m, const FreeParam& p, std::vector<double>& u, double v) {
  switch (p.kind) {
    case FreeParam::EffectParam: m.effects.at(p.effect, p.index) = v; break;
    case FreeParam::Trim:
      if (p.index >= static_cast<int>(m.trim.size())) m.trim.resize(p.index + 1, 0.0);
      m.trim[p.index] = v;
      break;
    case FreeParam::Coefficient: u[p.index] = v; break;
  }
}

void bounds_of(const FreeParam& p, double& lo, double& hi) {
  lo = -1e300;
  hi = 1e300;
  if (p.kind == FreeParam::EffectParam) {
    lo = effect_spec(p.effect).parameters.at(p.index).lower;
    hi = effect_spec(p.effect).parameters.at(p.index).upper;
  } else if (p.kind == FreeParam::Trim) {
    lo = -deg2rad(15.0);
    hi = deg2rad(15.0);
  }
}

/// Does parameter p change the residuals of a flight of glider g?
bool touches(const FreeParam& p, int g) { return p.kind != FreeParam::Trim || p.index == g; }

}  // namespace

FitOutcome DiagnosisData::fit(const DiagModel& start, const std::vector<int>& flights,
                              const std::vector<FreeParam>& free, const std::vector<LaunchParams>* warm,
                              int max_iterations) const {
  const int iterations_max = max_iterations > 0 ? max_iterations : o_.max_iterations;
  if (flights.empty()) throw InputError("no flights to fit");
  if (!start.coefficients) throw InputError("no coefficient model");
  const auto t_start = std::chrono::steady_clock::now();
  FitContext C(*this, *impl_, flights);
  const int nf = static_cast<int>(flights.size());
  const int np = static_cast<int>(free.size());
  const bool trial_fallback = o_.trial_fallback;
  const double s2 = d_.tracking_sigma_m * d_.tracking_sigma_m;
  DiagModel model = start;
  if (model.trim.size() < gliders_.size()) model.trim.resize(gliders_.size(), 0.0);
  const int nl = launch_count(model.effects);
  std::vector<double> u = C.centre_offsets(start, free);
  const bool coef = !u.empty();
  std::vector<double> scale(np), lo(np), hi(np);
  for (int k = 0; k < np; ++k) {
    scale[k] = this->scale(free[k]);
    bounds_of(free[k], lo[k], hi[k]);
  }

  auto aero = C.tables(model.coefficients);
  auto S = C.setup(model, aero);
  std::vector<LaunchParams> L;
  std::vector<double> lr;
  std::vector<Eigen::VectorXd> R;
  if (warm && static_cast<int>(warm->size()) == nf) L = *warm;
  double sse = C.fit_all(*S, L, lr, warm && static_cast<int>(warm->size()) == nf, R);
  int iterations = 0;
  // Tikhonov pull of free centre values toward the start model (u = 0).
  const double reg2 = coef ? o_.coefficient_regularisation_m * o_.coefficient_regularisation_m : 0.0;
  auto penalty = [&](const std::vector<double>& uu) {
    double p = 0;
    for (int k = 0; k < np; ++k)
      if (free[k].kind == FreeParam::Coefficient) p += reg2 * uu[free[k].index] * uu[free[k].index];
    return p;
  };

  if (np > 0) {
    double lambda = 1e-3;
    int refreshed = 0;
    for (int it = 0; it < iterations_max; ++it) {
      // Perturbed setups, one per free parameter.
      std::vector<std::unique_ptr<Setup>> Sp(np);
      std::vector<double> h(np);
      for (int k = 0; k < np; ++k) {
        DiagModel mp = model;
        std::vector<double> up = u;
        const double v = get_param(model, free[k], u);
        // Forward difference inward from an upper bound.
        h[k] = 1e-4 * scale[k] * (free[k].kind == FreeParam::Coefficient ? 1.0 / scale[k] : 1.0);
        if (v + h[k] > hi[k]) h[k] = -h[k];
        set_param(mp, free[k], up, v + h[k]);
        if (free[k].kind == FreeParam::Coefficient) Sp[k] = C.setup(mp, C.tables(C.coefficients_of(mp, up)));
        else Sp[k] = C.setup(mp, aero);
      }
      // Per flight: launch Jacobian, parameter Jacobian, projection.
      std::vector<Eigen::MatrixXd> Jp(nf), G(nf);
      parallel_for(nf, threads_, [&](int f) {
        const int fi = flights[f];
        const int g = flight_glider_[fi];
        const Eigen::VectorXd& r0 = R[f];
        const int m = static_cast<int>(r0.size());
        const Eigen::MatrixXd JL = C.launch_jacobian(*S, fi, L[f], r0, nl);
        Eigen::MatrixXd JT = Eigen::MatrixXd::Zero(m, np);
        Eigen::VectorXd r1;
        for (int k = 0; k < np; ++k) {
          if (!touches(free[k], g)) continue;
          C.residuals(*Sp[k], fi, L[f], r1);
          // Column in units of the parameter's scale (coefficients: u is already scaled).
          const double unit = free[k].kind == FreeParam::Coefficient ? 1.0 : scale[k];
          JT.col(k) = (r1 - r0) / h[k] * unit;
        }
        const Eigen::HouseholderQR<Eigen::MatrixXd> qr(JL);
        const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(m, nl);
        const Eigen::MatrixXd QtJ = Q.transpose() * JT;
        Jp[f] = JT - Q * QtJ;
        const Eigen::MatrixXd Rm = qr.matrixQR().topRows(nl).triangularView<Eigen::Upper>();
        G[f] = Rm.triangularView<Eigen::Upper>().solve(QtJ);
        if (!G[f].allFinite()) G[f].setZero();
      });
      Eigen::MatrixXd H = Eigen::MatrixXd::Zero(np, np);
      Eigen::VectorXd grad = Eigen::VectorXd::Zero(np);
      for (int f = 0; f < nf; ++f) {
        H += Jp[f].transpose() * Jp[f];
        grad += Jp[f].transpose() * R[f];
      }
      for (int k = 0; k < np; ++k)
        if (free[k].kind == FreeParam::Coefficient) {
          H(k, k) += reg2;
          grad(k) += reg2 * u[free[k].index];
        }
      bool accepted = false;
      for (int trial = 0; trial < 6 && !accepted; ++trial) {
        Eigen::MatrixXd A = H;
        for (int k = 0; k < np; ++k) A(k, k) += lambda * std::max(H(k, k), 1e-9) + 1e-12;
        const Eigen::VectorXd step = -A.ldlt().solve(grad);  // in scale units
        if (!step.allFinite()) break;
        DiagModel mt = model;
        std::vector<double> ut = u;
        Eigen::VectorXd taken(np);
        for (int k = 0; k < np; ++k) {
          const double v = get_param(model, free[k], u);
          const double unit = free[k].kind == FreeParam::Coefficient ? 1.0 : scale[k];
          const double nv = std::clamp(v + unit * step(k), lo[k], hi[k]);
          set_param(mt, free[k], ut, nv);
          taken(k) = (nv - v) / unit;
        }
        if (taken.norm() < 1e-12) break;
        std::vector<LaunchParams> Lt = L;
        for (int f = 0; f < nf; ++f) {
          const Eigen::VectorXd dL = -G[f] * taken;
          for (int k = 0; k < nl; ++k) *launch_value(Lt[f], k) += dL(k);
          Lt[f].speed = std::max(Lt[f].speed, 0.05);
        }
        auto at = coef ? C.tables(C.coefficients_of(mt, ut)) : aero;
        auto St = C.setup(mt, at);
        std::vector<double> lrt = lr;
        std::vector<Eigen::VectorXd> Rt;
        // Warm starts only: a trial's gain must come from the parameters, not
        // from a launch that a fresh multi-start happens to fit better.
        const double sset = C.fit_all(*St, Lt, lrt, true, Rt, trial_fallback);
        if (std::getenv("PTEROMYS_DIAG_DEBUG"))
          std::fprintf(stderr, "it %d trial %d lambda %g step %g -> sse %g (from %g) sims %ld refine its/call %g\n", it,
                       trial, lambda, taken(0), sset, sse, static_cast<long>(C.sims),
                       double(C.refine_iterations) / std::max<long>(1, C.refines));
        if (std::isfinite(sset) && sset + penalty(ut) < sse + penalty(u)) {
          const double sset2 = sset;
          const double obj_prev = sse + penalty(u), obj_new = sset + penalty(ut);
          const double rel = (obj_prev - obj_new) / obj_prev;
          model = mt;
          u = ut;
          aero = at;
          S = std::move(St);
          L = Lt;
          lr = lrt;
          R = Rt;
          sse = sset2;
          accepted = true;
          lambda = std::max(lambda / 5, 1e-7);
          ++iterations;
          // Converged when the gain is a small fraction of the SSE or of one
          // unit of chi-square (tracking noise): nothing a test could see.
          if (rel < o_.tolerance || obj_prev - obj_new < 0.2 * s2) {
            // Before stopping, multi-start the flights that still fit badly
            // (their launch may sit in a basin the model has left); go on
            // iterating if that changed the fit noticeably.
            const double before = sse;
            sse = C.refresh(*S, L, lr, R);
            if (!(before - sse > 0.2 * s2) || refreshed >= 2) it = iterations_max;
            ++refreshed;
          }
        } else {
          lambda *= 10;
        }
      }
      if (!accepted) break;
    }
  }

  FitOutcome out;
  if (coef) model.coefficients = C.coefficients_of(model, u);
  out.model = model;
  out.flights.resize(nf);
  parallel_for(nf, threads_, [&](int f) {
    FlightOutcome& fo = out.flights[f];
    fo.flight = flights[f];
    fo.launch = L[f];
    Track tr;
    Eigen::VectorXd r;
    C.residuals(*S, flights[f], L[f], r, &tr);
    fo.residual.resize(r.size() / 2);
    for (int i = 0; i < static_cast<int>(fo.residual.size()); ++i) fo.residual[i] = {r(2 * i), r(2 * i + 1)};
    fo.sse = r.squaredNorm();
    fo.states = tr.states;
    fo.left_model_range = tr.left_model_range;
  });
  out.sse = 0;
  for (const auto& fo : out.flights) {
    out.sse += fo.sse;
    out.points += static_cast<int>(fo.residual.size());
  }
  out.launch_parameters = nl * nf;
  out.free_parameters = np;
  out.iterations = iterations;
  out.simulations = C.sims;
  if (std::getenv("PTEROMYS_FIT_STATS"))
    std::fprintf(stderr,
                 "fit: %d flights, %d free, %d iterations, %.1f s: %ld simulations, %ld in %ld trial fallbacks "
                 "(%ld kept), %ld in refreshes; rmse %.4g m\n",
                 nf, np, iterations, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(),
                 static_cast<long>(C.sims), static_cast<long>(C.fallback_sims), static_cast<long>(C.fallbacks),
                 static_cast<long>(C.fallbacks_helped),
                 static_cast<long>(C.refresh_sims), out.rmse());
  return out;
}

Eigen::MatrixXd DiagnosisData::projected_jacobian(const FitOutcome& at, const std::vector<FreeParam>& free) const {
  std::vector<int> flights;
  for (const auto& f : at.flights) flights.push_back(f.flight);
  FitContext C(*this, *impl_, flights);
  const int nf = static_cast<int>(flights.size());
  const int np = static_cast<int>(free.size());
  const DiagModel& model = at.model;
  const int nl = launch_count(model.effects);
  const std::vector<double> u = C.centre_offsets(model, free);
  auto aero = C.tables(model.coefficients);
  auto S = C.setup(model, aero);
  std::vector<std::unique_ptr<Setup>> Sp(np);
  std::vector<double> h(np), unit(np);
  for (int k = 0; k < np; ++k) {
    double lo, hi;
    bounds_of(free[k], lo, hi);
    DiagModel mp = model;
    std::vector<double> up = u;
    const double v = get_param(model, free[k], u);
    const double sc = scale(free[k]);
    unit[k] = free[k].kind == FreeParam::Coefficient ? 1.0 : sc;
    h[k] = 1e-4 * unit[k];
    if (v + h[k] > hi) h[k] = -h[k];
    set_param(mp, free[k], up, v + h[k]);
    Sp[k] = free[k].kind == FreeParam::Coefficient ? C.setup(mp, C.tables(C.coefficients_of(mp, up))) : C.setup(mp, aero);
  }
  std::vector<int> offset(nf + 1, 0);
  for (int f = 0; f < nf; ++f)
    offset[f + 1] = offset[f] + 2 * static_cast<int>(d_.flights[flights[f]].points.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(offset[nf], np);
  parallel_for(nf, threads_, [&](int f) {
    const int fi = flights[f];
    const int g = flight_glider_[fi];
    Eigen::VectorXd r0, r1;
    C.residuals(*S, fi, at.flights[f].launch, r0);
    const int m = static_cast<int>(r0.size());
    const Eigen::MatrixXd JL = C.launch_jacobian(*S, fi, at.flights[f].launch, r0, nl);
    Eigen::MatrixXd JT = Eigen::MatrixXd::Zero(m, np);
    for (int k = 0; k < np; ++k) {
      if (!touches(free[k], g)) continue;
      C.residuals(*Sp[k], fi, at.flights[f].launch, r1);
      JT.col(k) = (r1 - r0) / h[k] * unit[k];
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(JL);
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(m, nl);
    J.middleRows(offset[f], m) = JT - Q * (Q.transpose() * JT);
  });
  return J;
}

DiagModel DiagnosisData::linear_step(const FitOutcome& at, const std::vector<FreeParam>& free,
                                     const Eigen::MatrixXd& J, const std::vector<int>& cols,
                                     double* predicted_sse, double fraction) const {
  const int np = static_cast<int>(free.size());
  if (!(fraction > 0 && fraction <= 1)) throw InputError("linear step: the fraction of the step must be in (0, 1]");
  int m = 0;
  for (const auto& f : at.flights) m += 2 * static_cast<int>(f.residual.size());
  if (J.rows() != m || J.cols() != np) throw InputError("linear step: the Jacobian does not match the fit and its parameters");
  Eigen::VectorXd r(m);
  int k = 0;
  for (const auto& f : at.flights)
    for (const auto& v : f.residual) {
      r(k++) = v.x;
      r(k++) = v.y;
    }
  int nc = 0;
  for (int c : cols) {
    if (c < 0 || c >= np) throw InputError("linear step: parameter index out of range");
    nc += free[c].kind == FreeParam::Coefficient ? 1 : 0;
  }
  // [J; reg I] theta = [-r; 0] (the pull rows only for centre values).
  const double reg = o_.coefficient_regularisation_m;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m + nc, static_cast<int>(cols.size()));
  Eigen::VectorXd y = Eigen::VectorXd::Zero(m + nc);
  y.head(m) = -r;
  int row = m;
  for (std::size_t j = 0; j < cols.size(); ++j) {
    A.col(static_cast<int>(j)).head(m) = J.col(cols[j]);
    if (free[cols[j]].kind == FreeParam::Coefficient) A(row++, static_cast<int>(j)) = reg;
  }
  Eigen::VectorXd th = A.colPivHouseholderQr().solve(y);
  if (!th.allFinite()) th.setZero();
  th *= fraction;
  if (predicted_sse) *predicted_sse = (A.topRows(m) * th - y.head(m)).squaredNorm();
  DiagModel model = at.model;
  if (model.trim.size() < gliders_.size()) model.trim.resize(gliders_.size(), 0.0);
  std::vector<double> u;
  std::shared_ptr<const RbfModel> rbf;
  if (nc > 0) {
    rbf = std::dynamic_pointer_cast<const RbfModel>(model.coefficients);
    if (!rbf) throw InputError("coefficient parameters need an RBF model");
    u.assign(3 * rbf->centres().size(), 0.0);
  }
  for (std::size_t j = 0; j < cols.size(); ++j) {
    const FreeParam& p = free[cols[j]];
    if (p.kind == FreeParam::Coefficient) {
      if (p.index < 0 || p.index >= static_cast<int>(u.size())) throw InputError("coefficient parameter out of range");
      u[p.index] += th(static_cast<int>(j));
      continue;
    }
    double lo, hi;
    bounds_of(p, lo, hi);
    const double v = get_param(model, p, u) + th(static_cast<int>(j)) * scale(p);
    set_param(model, p, u, std::clamp(v, lo, hi));
  }
  if (rbf) {
    std::vector<Coefficients> v;
    for (const auto& c : rbf->centres()) v.push_back(c.value);
    model.coefficients = moved_values(*rbf, v, u);
  }
  return model;
}

}  // namespace pteromys
