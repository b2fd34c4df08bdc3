// Fit reports, held-out predictions and synthetic flight datasets.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#include "pteromys/fit.hpp"
#include "pteromys/mass.hpp"

namespace pteromys {
using nlohmann::json;

namespace {

json launch_json(const LaunchParams& p) {
  return {{"t_s", p.t},           {"x_m", p.x},
          {"y_m", p.y},           {"speed_m_s", p.speed},
          {"climb_deg", rad2deg(p.climb)}, {"pitch_deg", rad2deg(p.pitch)},
          {"pitch_rate_deg_s", rad2deg(p.pitch_rate)}};
}

json centre_json(const RbfCentre& c) {
  return {{"alpha_deg", rad2deg(c.alpha)}, {"re", c.re}, {"xi_l_deg", rad2deg(c.xi_l)},
          {"xi_t_deg", rad2deg(c.xi_t)},   {"cd", c.value.cd}, {"cl", c.value.cl}, {"cm", c.value.cm}};
}

}  // namespace

json fit_report_json(const FitResult& r, const FitOptions& o) {
  json j;
  j["format"] = "pteromys-fit/1";
  j["fit_rmse_m"] = r.rmse_m;
  j["centres"] = r.model ? static_cast<int>(r.model->centres().size()) : 0;
  j["flights"] = static_cast<int>(r.flights.size());
  j["points"] = r.points;
  j["prior_rmse_m"] = r.prior_rmse_m;
  j["stop_reason"] = r.stop_reason;
  j["history"] = json::array();
  for (const auto& s : r.history) {
    json h = {{"centres", s.centres},   {"rmse_m", s.rmse_m},         {"accepted", s.accepted}, {"bic", s.bic},
              {"seconds", s.seconds},   {"iterations", s.iterations}, {"simulations", s.simulations}};
    if (s.has_added) {
      h["added"] = centre_json(s.added);
      h["predicted_gain_m2"] = s.predicted_gain;
    }
    j["history"].push_back(h);
  }
  j["per_flight"] = json::array();
  int outside = 0;
  for (const auto& f : r.flights) {
    outside += f.left_model_range ? 1 : 0;
    j["per_flight"].push_back({{"flight", f.flight},
                               {"glider", f.glider},
                               {"points", f.points},
                               {"rmse_m", f.rmse_m},
                               {"launch_rmse_m", f.launch_rmse_m},
                               {"max_error_m", f.max_error_m},
                               {"max_alpha_deg", rad2deg(f.max_alpha)},
                               {"left_model_range", f.left_model_range},
                               {"launch", launch_json(f.launch)}});
  }
  j["flights_outside_model_range"] = outside;
  j["timings"] = {{"total_s", r.seconds},
                  {"launch_fits_s", r.launch_seconds},
                  {"coefficient_fits_s", r.coefficient_seconds},
                  {"insertion_s", r.insertion_seconds},
                  {"simulations", r.simulations},
                  {"threads", r.threads}};
  j["options"] = {{"max_centres", o.max_centres},
                  {"launch_points", o.launch.points},
                  {"fit_pitch_rate", o.launch.fit_pitch_rate},
                  {"information_criterion", o.information_criterion},
                  {"min_improvement", o.min_improvement},
                  {"max_rounds", o.max_rounds},
                  {"max_iterations", o.max_iterations},
                  {"candidates", o.candidates},
                  {"insertion_tries", o.insertion_tries},
                  {"regularisation_m", o.regularisation_m},
                  {"robust_m", o.robust_m},
                  {"prior", r.model && r.model->prior() ? "flat_plate" : "none"},
                  {"dt_s", o.launch.track.sim.dt},
                  {"dz_m", o.aero.dz}};
  return j;
}

std::vector<FlightPrediction> predict_flights(const Dataset& d, std::shared_ptr<const CoefficientModel> model,
                                              const FitOptions& o) {
  if (d.flights.empty()) throw InputError("the dataset has no flights");
  const auto problems = dataset_problems(d);
  if (!problems.empty()) throw InputError("invalid dataset: " + problems.front());
  Environment env;
  env.air_density = d.air_density;
  env.air_viscosity = d.air_viscosity;
  env.gravity = d.gravity;
  LaunchFitOptions lo = o.launch;
  lo.track.gravity = d.gravity;
  lo.fit_pitch = model != nullptr;
  std::map<std::string, std::shared_ptr<const MountedGlider>> mounted;
  for (const auto& [key, g] : d.gliders)
    if (model) mounted[key] = std::make_shared<const MountedGlider>(mount(g, model, env, o.aero));
  std::vector<FlightPrediction> out(d.flights.size());
  const int threads = o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  std::exception_ptr err;
  std::mutex mu;
  std::atomic<int> next{0};
  auto work = [&] {
    for (;;) {
      const int i = next++;
      if (i >= static_cast<int>(d.flights.size())) break;
      try {
        const TrackedFlight& f = d.flights[i];
        auto git = d.gliders.find(f.glider);
        if (git == d.gliders.end()) throw InputError("flight '" + f.name + "' uses unknown glider '" + f.glider + "'");
        const MassProperties mp = mass_properties(git->second);
        const RigidBody body{mp.mass, mp.inertia};
        const NoAero none;
        std::unique_ptr<QuasiStaticAero> qa;
        if (model) qa = std::make_unique<QuasiStaticAero>(*mounted.at(f.glider));
        const AeroForces& aero = model ? static_cast<const AeroForces&>(*qa) : static_cast<const AeroForces&>(none);
        FlightPrediction p;
        p.flight = f.name;
        p.glider = f.glider;
        p.launch_points = std::min<int>(lo.points, f.points.size());
        LaunchFit lf;
        try {
          lf = fit_launch(aero, body, f.points, lo);
        } catch (const InputError& e) {
          throw InputError("flight '" + f.name + "': " + e.what());
        }
        p.launch = lf.launch;
        for (const auto& q : f.points) {
          p.t.push_back(q.t);
          p.tracked.push_back({q.x, q.y});
        }
        const Track tr = simulate_track(aero, body, p.launch, p.t, lo.track);
        p.simulated = tr.positions;
        p.max_alpha = tr.max_alpha;
        p.left_model_range = tr.left_model_range;
        double s = 0, sa = 0;
        int na = 0;
        for (std::size_t j = 0; j < p.t.size(); ++j) {
          const double e2 = std::pow(norm(p.simulated[j] - p.tracked[j]), 2);
          s += e2;
          if (static_cast<int>(j) >= lo.points) {
            sa += e2;
            ++na;
          }
        }
        p.rmse_m = std::sqrt(s / p.t.size());
        p.rmse_after_m = na ? std::sqrt(sa / na) : 0.0;
        out[i] = std::move(p);
      } catch (...) {
        std::lock_guard<std::mutex> lk(mu);
        if (!err) err = std::current_exception();
        next = static_cast<int>(d.flights.size());
      }
    }
  };
  for (int t = 0; t < std::min<int>(threads, d.flights.size()); ++t) pool.emplace_back(work);
  for (auto& t : pool) t.join();
  if (err) std::rethrow_exception(err);
  return out;
}

double predictions_rmse(const std::vector<FlightPrediction>& ps, bool after) {
  double s = 0;
  long n = 0;
  for (const auto& p : ps)
    for (std::size_t j = 0; j < p.t.size(); ++j) {
      if (after && static_cast<int>(j) < p.launch_points) continue;
      s += std::pow(norm(p.simulated[j] - p.tracked[j]), 2);
      ++n;
    }
  return n ? std::sqrt(s / n) : 0.0;
}

Dataset synthetic_dataset(const std::map<std::string, Glider>& gliders, std::shared_ptr<const CoefficientModel> model,
                          const SyntheticOptions& o) {
  if (gliders.empty()) throw InputError("no gliders to fly");
  if (!model) throw InputError("no model to simulate with");
  if (o.points_min < 6 || o.points_max < o.points_min) throw InputError("points per flight must be at least 6");
  if (!(o.frame_rate_hz > 0) || !(o.noise_m >= 0)) throw InputError("frame rate must be positive, noise non-negative");
  Dataset d;
  d.frame_rate_hz = o.frame_rate_hz;
  d.tracking_sigma_m = o.noise_m > 0 ? o.noise_m : 1e-6;
  d.air_density = o.env.air_density;
  d.air_viscosity = o.env.air_viscosity;
  d.gravity = o.env.gravity;
  d.extra_columns = {"release_t_s", "release_speed_m_s", "release_climb_deg", "release_pitch_deg"};
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::normal_distribution<double> N(0.0, 1.0);
  auto uni = [&](double a, double b) { return a + (b - a) * U(rng); };
  TrackOptions to;
  to.sim = o.sim;
  to.gravity = o.env.gravity;
  to.height_offset = 0;                 // a real ground at y = 0
  to.continue_outside_range = false;    // stalls and flips end a flight, as they would
  for (const auto& [key, g] : gliders) {
    validate(g);
    d.gliders[key] = g;
    d.glider_files[key] = "gliders/" + key + ".glider.json";
    const MountedGlider mg = mount(g, model, o.env, o.aero);
    const QuasiStaticAero qa(mg);
    const RigidBody body{mg.mass().mass, mg.mass().inertia};
    for (int k = 0; k < o.flights_per_glider; ++k) {
      bool done = false;
      for (int attempt = 0; attempt < 50 && !done; ++attempt) {
        LaunchParams rel;
        rel.t = 0;
        rel.x = 0;
        rel.y = o.height;
        rel.speed = uni(o.speed_min, o.speed_max);
        rel.climb = deg2rad(uni(o.climb_min_deg, o.climb_max_deg));
        rel.pitch = rel.climb + deg2rad(uni(o.alpha_min_deg, o.alpha_max_deg));
        const double delay = uni(0.0, o.delay_max_s);
        const int n = o.points_min + static_cast<int>(U(rng) * (o.points_max - o.points_min + 1) * 0.999999);
        std::vector<double> times;
        for (int i = 0; i < n; ++i) times.push_back(delay + i / o.frame_rate_hz);
        const Track tr = simulate_track(qa, body, rel, times, to);
        if (tr.ended_early) continue;
        const double origin = uni(0.0, 10.0);  // the dataset's arbitrary time origin
        TrackedFlight f;
        f.name = key + "-" + std::to_string(k + 1);
        f.glider = key;
        for (int i = 0; i < n; ++i)
          f.points.push_back({origin + times[i], tr.positions[i].x + o.noise_m * N(rng),
                              tr.positions[i].y + o.noise_m * N(rng)});
        auto num = [](double v) {
          std::ostringstream s;
          s.precision(10);
          s << v;
          return s.str();
        };
        f.extra["release_t_s"] = num(origin);
        f.extra["release_speed_m_s"] = num(rel.speed);
        f.extra["release_climb_deg"] = num(rad2deg(rel.climb));
        f.extra["release_pitch_deg"] = num(rad2deg(rel.pitch));
        d.flights.push_back(std::move(f));
        done = true;
      }
      if (!done)
        throw InputError("glider '" + key + "' could not fly " + std::to_string(o.points_min) +
                         " tracked frames from the random launches (it stalls, flips or lands)");
    }
  }
  return d;
}

}  // namespace pteromys
