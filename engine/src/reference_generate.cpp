// Reference simulator: launcher, camera and synthetic flight datasets.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <exception>
#include <mutex>
#include <numeric>
#include <thread>

#include "pteromys/reference.hpp"
#include "pteromys/analysis.hpp"
#include "pteromys/effects.hpp"

namespace pteromys {
namespace {

// splitmix64 (Steele, Lea & Flood 2014): seeds and stream keys.
std::uint64_t splitmix(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::uint64_t key(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a ^ (b * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull);
  return splitmix(x);
}

// xoshiro256** (Blackman & Vigna 2018) with Box-Muller normals: the same
// numbers on every platform, unlike std::normal_distribution.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) {
    for (auto& v : s_) v = splitmix(seed);
  }
  std::uint64_t next() {
    const std::uint64_t r = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return r;
  }
  double uniform() { return (next() >> 11) * (1.0 / 9007199254740992.0); }
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2 * std::log(u1));
    spare_ = r * std::sin(2 * kPi * u2);
    has_spare_ = true;
    return r * std::cos(2 * kPi * u2);
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_ = 0;
  bool has_spare_ = false;
};

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

void check_range(double v, double lo, double hi, const std::string& what) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(what + " must be between " + num(lo) + " and " + num(hi) + ", got " + num(v));
}

void check_options(const GenerateOptions& o) {
  if (o.flights_per_glider < 1 || o.flights_per_glider > 10000)
    throw InputError("flights per glider must be between 1 and 10000");
  if (o.points_min < 6) throw InputError("a flight needs at least 6 tracked points (points_min >= 6)");
  if (o.points_max < o.points_min || o.points_max > 100000)
    throw InputError("points_max must be at least points_min (and at most 100000)");
  check_range(o.camera.frame_rate_hz, 1.0, 10000.0, "frame rate [Hz]");
  check_range(o.camera.noise_sigma_m, 0.0, 10.0, "tracking noise [m]");
  check_range(o.camera.scale, 0.1, 10.0, "camera scale");
  check_range(o.camera.roll_deg, -90.0, 90.0, "camera roll [deg]");
  // the camera as the camera effect leaves it (a scale error of -2 mirrored
  // the flights, which fit then refused as flying backwards)
  {
    const double f = o.effects.camera.factor();
    check_range(o.camera.scale * (1 + f * o.camera.scale_error), 0.1, 10.0,
                "camera scale with its scale error at the camera effect's strength");
    check_range(o.camera.roll_deg + f * o.camera.roll_error_deg, -90.0, 90.0,
                "camera roll with its roll error at the camera effect's strength [deg]");
  }
  check_time_step(o.dt, "the time step");
  if (o.retrim) check_range(o.retrim_alpha_deg, -5.0, 15.0, "trim angle of attack [deg]");
  const LauncherModel& l = o.launcher;
  check_range(l.speed_min, 0.1, 100.0, "launch speed [m/s]");
  check_range(l.speed_max, l.speed_min, 100.0, "maximum launch speed [m/s]");
  check_range(l.climb_min_deg, -89.0, 89.0, "launch climb angle [deg]");
  check_range(l.climb_max_deg, l.climb_min_deg, 89.0, "maximum launch climb angle [deg]");
  check_range(l.height, 0.01, 100.0, "launch height [m]");
  for (double s : {l.speed_sigma, l.climb_sigma_deg, l.pitch_sigma_deg, l.pitch_rate_sigma_deg_s,
                   l.rotation_sigma_deg_s, l.height_sigma, l.release_sigma_s})
    check_range(s, 0.0, 1000.0, "a launcher spread");
  check_range(l.pitch_offset_deg, -90.0, 90.0, "launch pitch offset [deg]");
  check_range(l.pitch_rate_deg_s, -5000.0, 5000.0, "launch pitch rate [deg/s]");
  check_range(l.rotation_deg_s, -5000.0, 5000.0, "launch rotation [deg/s]");
  check_range(l.release_delay_s, 0.0, 100.0, "release delay [s]");
  check_range(o.wind_m_s, -50.0, 50.0, "wind [m/s]");
  for (const auto& n : Effects::names()) {
    const double f = o.effects[n].factor();
    if (!std::isfinite(f) || std::abs(f) > 100) throw InputError("strength of effect '" + n + "' is out of range");
  }
}

}  // namespace

Glider retrim_glider(const std::string& key, const Glider& g, double alpha_deg, const ReferenceOptions& aero,
                     const Environment& env, double* turned_deg, double* nose_weight_kg) {
  if (turned_deg) *turned_deg = 0;
  if (nose_weight_kg) *nose_weight_kg = 0;
  const GliderFeatures f = glider_features(g);
  if (f.trim_wing < 0) return g;
  const double target = deg2rad(alpha_deg);
  const std::string& wname = g.wings[f.trim_wing].name;
  const std::string what = "glider '" + key + "' cannot be trimmed to glide at " + num(alpha_deg) +
                           " degrees angle of attack in this reality";
  const double chord = f.wings[f.main_wing].mean_chord;
  const double mass0 = mass_properties(g).mass;
  // Nose weight, if any is needed, goes 5 mm behind the fuselage's tip.
  double nose_x = -1e9, nose_y = 0;
  for (const auto& q : g.fuselage)
    if (q.x > nose_x) {
      nose_x = q.x;
      nose_y = q.y;
    }
  nose_x -= 0.005;
  auto build = [&](double delta_deg, double nose_kg) {
    Glider t = g;
    t.wings[f.trim_wing].mount.angle_deg += delta_deg;
    if (nose_kg > 0) t.ballast.push_back({"trim weight", nose_kg, nose_x, nose_y});
    return t;
  };
  for (int step = 0; step <= 20; ++step) {
    const double nose_kg = 0.05 * step * mass0;  // up to the glider's own mass
    // The moment at the target angle of attack as a function of the turn of
    // the trim wing: it falls as a tail's incidence rises (rises for a
    // canard); its zero is the trim.
    auto moment_at = [&](double delta_deg) {
      const Glider t = build(delta_deg, nose_kg);
      const ReferenceAero ref(t, mass_properties(t).cg, aero, env);
      return level_forces(ref, 5.0, target).moment;
    };
    double a = -15.0, b = 15.0;
    double fa = moment_at(a);
    if (!(fa * moment_at(b) <= 0))
      throw InputError(what + " by turning its wing '" + wname + "' within 15 degrees either way");
    for (int i = 0; i < 50 && b - a > 1e-5; ++i) {
      const double m = 0.5 * (a + b);
      const double fm = moment_at(m);
      if ((fm < 0) == (fa < 0)) {
        a = m;
        fa = fm;
      } else {
        b = m;
      }
    }
    const double delta = 0.5 * (a + b);
    const Glider t = build(delta, nose_kg);
    // Pitch stability there: static margin -(dM/dgamma) / (dL/dgamma) / chord >= 5 %.
    const ReferenceAero ref(t, mass_properties(t).cg, aero, env);
    const double h = deg2rad(0.5);
    const GliderForces up = level_forces(ref, 5.0, target + h), down = level_forces(ref, 5.0, target - h);
    const double dM = up.moment - down.moment, dL = up.lift - down.lift;
    if (!(dL > 0 && -dM / dL >= 0.05 * chord)) continue;  // add nose weight
    try {
      validate(t);
    } catch (const InputError& e) {
      throw InputError("glider '" + key + "' trimmed for this reality (wing '" + wname + "' turned by " +
                       num(delta) + " degrees) is no longer a valid glider: " + e.what());
    }
    if (turned_deg) *turned_deg = delta;
    if (nose_weight_kg) *nose_weight_kg = nose_kg;
    return t;
  }
  throw InputError(what + ": it is not pitch-stable even with its own mass again as nose weight");
}

namespace {

// Cubic Hermite position of the flight at time t (relative to release).
Vec2 position_at(const Flight& f, double t) {
  const auto& s = f.samples;
  auto it = std::upper_bound(s.begin(), s.end(), t, [](double v, const FlightSample& a) { return v < a.t; });
  if (it == s.begin()) return {s.front().x, s.front().y};
  if (it == s.end()) return {s.back().x, s.back().y};
  const FlightSample& a = *(it - 1);
  const FlightSample& b = *it;
  const double h = b.t - a.t;
  if (!(h > 0)) return {a.x, a.y};
  const double u = (t - a.t) / h, u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  return {h00 * a.x + h10 * h * a.vx + h01 * b.x + h11 * h * b.vx,
          h00 * a.y + h10 * h * a.vy + h01 * b.y + h11 * h * b.vy};
}

bool valid_key(const std::string& k) {
  if (k.empty() || k.size() > 100) return false;
  for (char c : k)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  return k != "." && k != "..";
}

}  // namespace

Vec2 CameraModel::project(Vec2 p) const {
  return centre + scale * rotate(p - centre, deg2rad(roll_deg));
}

std::vector<TrackedPoint> track_flight(const Flight& f, double release_t, const CameraModel& camera,
                                       TrackWindow window, int n_points,
                                       const std::function<double()>& noise) {
  std::vector<TrackedPoint> out;
  if (f.samples.empty()) return out;
  const double fps = camera.frame_rate_hz;
  const double t_end = release_t + f.samples.back().t;
  const long k0 = static_cast<long>(std::ceil(release_t * fps - 1e-9));
  const long k1 = static_cast<long>(std::floor(t_end * fps + 1e-9));
  if (k1 < k0) return out;
  long first = k0, last = k1;
  if (window == TrackWindow::Launch) last = std::min(k1, k0 + n_points - 1);
  else if (window == TrackWindow::Landing) first = std::max(k0, k1 - n_points + 1);
  for (long k = first; k <= last; ++k) {
    const double t = k / fps;
    const Vec2 p = camera.project(position_at(f, t - release_t));
    TrackedPoint tp;
    tp.t = t;
    tp.x = p.x + camera.noise_sigma_m * noise();
    tp.y = p.y + camera.noise_sigma_m * noise();
    out.push_back(tp);
  }
  return out;
}

Dataset generate_dataset(const std::vector<std::pair<std::string, Glider>>& gliders,
                         const GenerateOptions& opt, GenerateStats* stats) {
  if (gliders.empty()) throw InputError("no gliders to generate flights for");
  check_options(opt);
  {
    std::vector<std::string> keys;
    for (const auto& [k, g] : gliders) {
      if (!valid_key(k))
        throw InputError("glider key '" + k + "' must be 1-100 letters, digits, '_', '-' or '.'");
      keys.push_back(k);
      validate(g);
    }
    std::sort(keys.begin(), keys.end());
    if (std::adjacent_find(keys.begin(), keys.end()) != keys.end())
      throw InputError("two gliders have the same key '" + *std::adjacent_find(keys.begin(), keys.end()) + "'");
  }

  const int ng = static_cast<int>(gliders.size());
  const int nf = opt.flights_per_glider;
  const int total = ng * nf;
  ReferenceOptions aero = opt.aero;
  aero.effects = opt.effects;
  const double f_rot = opt.effects.launch_rotation.factor();
  const double f_wind = opt.effects.wind.factor();
  const double f_cam = opt.effects.camera.factor();
  CameraModel cam = opt.camera;
  cam.scale = opt.camera.scale * (1 + f_cam * opt.camera.scale_error);
  cam.roll_deg = opt.camera.roll_deg + f_cam * opt.camera.roll_error_deg;
  SimOptions sim;
  sim.dt = opt.dt;
  sim.record_every = 1;
  sim.wind = {f_wind * opt.wind_m_s, 0.0};

  std::vector<std::vector<TrackedFlight>> results(ng);
  std::vector<Glider> flown(ng);  // as flown (trimmed for this reality when opt.retrim)
  std::atomic<int> next{0};
  std::mutex mtx;
  int done = 0;
  GenerateStats st;
  std::exception_ptr error;
  double setup_s = 0, sim_s = 0;

  auto worker = [&]() {
    for (;;) {
      const int gi = next.fetch_add(1);
      if (gi >= ng) return;
      {
        std::lock_guard<std::mutex> lk(mtx);
        if (error) return;
      }
      try {
        const auto& gkey = gliders[gi].first;
        const auto t0 = std::chrono::steady_clock::now();
        double turned = 0, nose_kg = 0;
        flown[gi] = opt.retrim ? retrim_glider(gkey, gliders[gi].second, opt.retrim_alpha_deg, aero, opt.env,
                                               &turned, &nose_kg)
                               : gliders[gi].second;
        const Glider& glider = flown[gi];
        const MassProperties mp = mass_properties(glider);
        const ReferenceAero ref(glider, mp.cg, aero, opt.env);
        const RigidBody body{mp.mass, mp.inertia};
        double speed_unit = 1.0;  // launch speeds are in m/s, or in glide speeds
        if (opt.launcher.speed_relative) {
          const Glide sg = steady_glide(ref, body, opt.env.gravity);
          if (!sg.exists)
            throw InputError("glider '" + gkey + "' has no steady glide in this reality (no pitch-stable "
                             "equilibrium with lift between -15 and 25 degrees angle of attack); launch speeds "
                             "relative to the glide speed need one (--retrim trims it)");
          speed_unit = sg.speed;
        }
        const auto t1 = std::chrono::steady_clock::now();
        // Climb-angle settings in a random order per glider (speeds in order).
        Rng grng(key(key(opt.seed, static_cast<std::uint64_t>(gi)), 0xC11Bull));
        std::vector<int> perm(nf);
        std::iota(perm.begin(), perm.end(), 0);
        for (int i = nf - 1; i > 0; --i)
          std::swap(perm[i], perm[static_cast<int>(grng.uniform() * (i + 1)) % (i + 1)]);
        int redrawn = 0, unstable = 0, dropped = 0;
        std::vector<TrackedFlight> flights;
        for (int fi = 0; fi < nf; ++fi) {
          const LauncherModel& L = opt.launcher;
          TrackedFlight best;
          bool ok = false;
          for (int attempt = 0; attempt < opt.max_attempts && !ok; ++attempt) {
            Rng rng(key(key(key(opt.seed, static_cast<std::uint64_t>(gi) + 1), static_cast<std::uint64_t>(fi) + 1),
                        static_cast<std::uint64_t>(attempt)));
            Launch l;
            l.speed = std::max(0.1, speed_unit * (L.speed_min + (fi + 0.5) / nf * (L.speed_max - L.speed_min) +
                                                      L.speed_sigma * rng.normal()));
            l.climb_deg = L.climb_min_deg + (perm[fi] + 0.5) / nf * (L.climb_max_deg - L.climb_min_deg) +
                          L.climb_sigma_deg * rng.normal();
            l.pitch_from_path = false;
            l.pitch_deg = l.climb_deg + L.pitch_offset_deg + L.pitch_sigma_deg * rng.normal();
            l.pitch_rate_deg_s = L.pitch_rate_deg_s + L.pitch_rate_sigma_deg_s * rng.normal();
            const double rot = L.rotation_deg_s + L.rotation_sigma_deg_s * rng.normal();
            l.pitch_rate_deg_s += f_rot * rot;
            l.height = std::max(0.01, L.height + L.height_sigma * rng.normal());
            const double release_t = std::max(0.0, L.release_delay_s + L.release_sigma_s * rng.normal());
            const int npts = opt.points_min +
                             static_cast<int>(rng.uniform() * (opt.points_max - opt.points_min + 1)) %
                                 (opt.points_max - opt.points_min + 1);
            SimOptions so = sim;
            if (opt.window == TrackWindow::Launch) {
              const double first = std::ceil(release_t * cam.frame_rate_hz - 1e-9) / cam.frame_rate_hz;
              so.t_max = first + (npts - 1) / cam.frame_rate_hz - release_t + 2 * opt.dt;
            } else {
              so.t_max = 30.0;
            }
            const Flight f = simulate(ref, body, l, so, opt.env.gravity);
            auto noise = [&rng]() { return rng.normal(); };
            std::vector<TrackedPoint> pts = track_flight(f, release_t, cam, opt.window, npts, noise);
            if (pts.size() < 6) {
              ++redrawn;
              continue;
            }
            ok = true;
            best.name = gkey + "-" + (fi + 1 < 10 ? "0" : "") + std::to_string(fi + 1);
            best.glider = gkey;
            best.points = std::move(pts);
            best.extra["true_speed_m_s"] = num(l.speed);
            if (L.speed_relative) best.extra["glide_speed_m_s"] = num(speed_unit);
            if (opt.retrim) {
              best.extra["trim_turn_deg"] = num(turned);
              best.extra["trim_weight_kg"] = num(nose_kg);
            }
            best.extra["true_climb_deg"] = num(l.climb_deg);
            best.extra["true_pitch_deg"] = num(l.pitch_deg);
            best.extra["true_pitch_rate_deg_s"] = num(l.pitch_rate_deg_s);
            best.extra["true_height_m"] = num(l.height);
            best.extra["true_release_t_s"] = num(release_t);
            const bool landed = f.end == FlightEnd::Ground;
            const std::string end = landed ? "ground" : f.end == FlightEnd::TimeLimit ? "time_limit" : "unstable";
            best.extra["true_end"] = end;
            if (end == "unstable") ++unstable;
          }
          if (!ok && opt.strict)
            throw InputError("glider '" + gkey + "': no launch in " + std::to_string(opt.max_attempts) +
                             " draws gave 6 tracked points (it hits the ground or tumbles at once)");
          if (ok) flights.push_back(std::move(best));
          else ++dropped;
          std::lock_guard<std::mutex> lk(mtx);
          ++done;
          if (opt.progress) opt.progress(done, total, gkey);
        }
        const auto t2 = std::chrono::steady_clock::now();
        std::lock_guard<std::mutex> lk(mtx);
        results[gi] = std::move(flights);
        st.redrawn += redrawn;
        st.unstable += unstable;
        st.dropped += dropped;
        setup_s += std::chrono::duration<double>(t1 - t0).count();
        sim_s += std::chrono::duration<double>(t2 - t1).count();
      } catch (...) {
        std::lock_guard<std::mutex> lk(mtx);
        if (!error) error = std::current_exception();
        return;
      }
    }
  };
  const int nt = std::clamp(opt.threads, 1, std::max(1, ng));
  if (nt == 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int i = 0; i < nt; ++i) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  if (error) std::rethrow_exception(error);

  Dataset d;
  d.frame_rate_hz = cam.frame_rate_hz;
  d.tracking_sigma_m = cam.noise_sigma_m;
  d.air_density = opt.env.air_density;
  d.air_viscosity = opt.env.air_viscosity;
  d.gravity = opt.env.gravity;
  for (int gi = 0; gi < ng; ++gi) {
    const auto& k = gliders[gi].first;
    const Glider& g = flown[gi];
    if (results[gi].empty()) {
      st.dropped_gliders.push_back(k);
      continue;
    }
    d.gliders[k] = g;
    d.glider_files[k] = "gliders/" + k + ".glider.json";
  }
  if (d.gliders.empty())
    throw InputError("no glider gave a single flight with 6 tracked points (they hit the ground or tumble at once)");
  d.extra_columns = {"true_speed_m_s", "true_climb_deg", "true_pitch_deg", "true_pitch_rate_deg_s",
                     "true_height_m", "true_release_t_s", "true_end"};
  if (opt.launcher.speed_relative) d.extra_columns.push_back("glide_speed_m_s");
  if (opt.retrim) {
    d.extra_columns.push_back("trim_turn_deg");
    d.extra_columns.push_back("trim_weight_kg");
  }
  for (auto& fl : results)
    for (auto& f : fl) d.flights.push_back(std::move(f));
  st.flights = static_cast<int>(d.flights.size());
  st.setup_seconds = setup_s;
  st.simulate_seconds = sim_s;
  if (stats) *stats = st;
  return d;
}

}  // namespace pteromys
