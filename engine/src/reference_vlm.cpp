// Reference simulator: vortex lattice of all wings, decambering against the
// flat-plate section law, fuselage friction, ground images, added mass.
// Formulas and sources: docs/reference_simulator.md.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <set>

#include <Eigen/Dense>

#include "pteromys/geometry.hpp"
#include "pteromys/reference.hpp"

namespace pteromys {
namespace {

constexpr double kInvFourPi = 1.0 / (4.0 * kPi);
constexpr double kTwoPi = 2.0 * kPi;

struct V3 {
  double x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double norm(V3 a) { return std::sqrt(dot(a, a)); }

inline double wrap(double a) {
  a = std::fmod(a + kPi, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  return a - kPi;
}

// Velocity at p induced by a straight vortex segment a -> b of unit strength
// (Biot-Savart), with a Kaufmann (Scully) core of radius rc: the factor
// h^2 / (h^2 + rc^2) on the perpendicular distance h to the segment's line.
V3 segment_velocity(V3 p, V3 a, V3 b, double rc) {
  const V3 r1 = p - a, r2 = p - b, r0 = b - a;
  const double n1 = norm(r1), n2 = norm(r2);
  if (n1 < 1e-14 || n2 < 1e-14) return {};
  const V3 c = cross(r1, r2);
  const double den = dot(c, c) + rc * rc * dot(r0, r0);
  if (den < 1e-30) return {};
  const double k = kInvFourPi * (dot(r0, (1.0 / n1) * r1) - dot(r0, (1.0 / n2) * r2)) / den;
  return k * c;
}

// Semi-infinite vortex from a along the unit direction d (to infinity).
V3 semi_infinite_velocity(V3 p, V3 a, V3 d, double rc) {
  const V3 r1 = p - a;
  const double n1 = norm(r1);
  if (n1 < 1e-14) return {};
  const V3 c = cross(d, r1);
  const double den = dot(c, c) + rc * rc;
  if (den < 1e-30) return {};
  return (kInvFourPi * (1.0 + dot(d, r1) / n1) / den) * c;
}

// Horseshoe: from infinity (along -d) to a, bound a -> b, b to infinity along d.
V3 horseshoe_velocity(V3 p, V3 a, V3 b, V3 d, double rc_bound, double rc_legs) {
  return segment_velocity(p, a, b, rc_bound) + semi_infinite_velocity(p, b, d, rc_legs) -
         semi_infinite_velocity(p, a, d, rc_legs);
}

inline V3 mirror_z(V3 a) { return {a.x, a.y, -a.z}; }

// Horseshoe of the z > 0 half plus its mirror image (symmetric loading).
V3 symmetric_horseshoe(V3 p, V3 a, V3 b, V3 d, double rcb, double rcl) {
  return horseshoe_velocity(p, a, b, d, rcb, rcl) +
         horseshoe_velocity(p, mirror_z(b), mirror_z(a), d, rcb, rcl);
}

// x-intervals (x_te, x_le) where the line z = const crosses a planform (x, z),
// upstream piece first.
std::vector<std::pair<double, double>> chord_intervals(const Polygon& poly, double z) {
  std::vector<double> xs;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = poly[i], q = poly[(i + 1) % n];
    if ((p.y <= z) != (q.y <= z)) xs.push_back(p.x + (z - p.y) * (q.x - p.x) / (q.y - p.y));
  }
  std::sort(xs.begin(), xs.end());
  std::vector<std::pair<double, double>> out;
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2)
    if (xs[i + 1] - xs[i] > 1e-12) out.push_back({xs[i], xs[i + 1]});
  std::reverse(out.begin(), out.end());
  return out;
}

struct Panel {
  int strip = 0, wing = 0;
  V3 a, b;          // bound vortex (z > 0 half), glider frame relative to the reference point
  V3 cp;            // control point (3/4 of the panel chord, mid-span)
  V3 normal;        // plate normal (n_x, n_y, 0)
  Vec2 bound_mid;   // (x, y) of the bound vortex at mid-span (2D strip theory)
  double s_bound = 0;  // distance of the bound vortex from the leading edge at mid-span [m]
  double rc = 0;       // core radius for interference and image influences [m]
};

struct StripInternal {
  ReferenceStrip geo;
  Vec2 n, c;          // plate normal and chord direction (toward the leading edge), glider frame
  Vec2 p34, pmid;     // 3/4-chord and mid-chord points (mid-span), relative to the reference
  double cn90 = 1.98; // separated normal force at 90 deg (with the finite-span factor)
  double t_over_c = 0;
  double added_mass = 0, added_inertia = 0;  // both halves, strength 1
  double sweep = 0;   // leading-edge sweep, positive when the edge moves aft outboard [rad]
};

// A piece of a wing's side edge (tip) between two bound vortices of the tip
// strip: the trailing legs of the panels ahead of it run along it (Lamar's
// side-edge suction analogy).
struct TipSegment {
  int strip = 0;
  int first_panel = 0, panels = 0;  // cumulative circulation of these panels runs along it
  V3 mid;                           // midpoint, glider frame
  Vec2 normal;                      // plate normal
  double length = 0;                // [m]
};

// A point where induced normal velocity is wanted: control points and tip segments.
struct Target {
  V3 p, normal;
  int wing = 0, strip = -1;  // strip -1: no 2D-strip part (side-edge points)
};

// Strip-level linear maps of one grid node. With the body velocity (u, w),
// the effective pitch rate q and the decambering delta (per strip):
//   c~ = (cu u + cw w + cq q) / V + cd delta     (strip normal-force coefficient)
//   cm = (mu u + mw w + mq q) / V + md delta     (moment about the quarter chord)
struct Node {
  Eigen::VectorXd cu, cw, cq, mu, mw, mq;
  Eigen::MatrixXd cd, md;
  // tip segments: cumulative circulation (gs) and induced normal velocity (ws)
  // per component of xi = (u, w, q, V delta_1..ns): nseg x (3 + ns)
  Eigen::MatrixXd gs, ws;
};

// Per-thread work space of an evaluation (no allocation per call).
struct Scratch {
  int ns = -1;
  Eigen::VectorXd nn, tt, gsep, w0, wi, g, dg, delta, F, F2, w2, step, c0, m0;
  Eigen::MatrixXd K, J, CD, MD;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
};

Scratch& scratch(int ns) {
  thread_local Scratch s;
  if (s.ns != ns) {
    s.ns = ns;
    for (auto* v : {&s.nn, &s.tt, &s.gsep, &s.w0, &s.wi, &s.g, &s.dg, &s.delta, &s.F, &s.F2, &s.w2, &s.step,
                    &s.c0, &s.m0})
      v->resize(ns);
    for (auto* m : {&s.K, &s.J, &s.CD, &s.MD}) m->resize(ns, ns);
    s.lu = Eigen::PartialPivLU<Eigen::MatrixXd>(ns);
  }
  return s;
}

struct FuselageTable {
  bool present = false;
  int n = 0;                       // directions over [0, 2 pi)
  std::vector<double> k_f, n_f;    // sum sqrt(l) dn, sum n sqrt(l) dn
  std::vector<double> w_e, n_e;    // frontal width, sum n dn (edges)
};

}  // namespace

struct ReferenceAero::Impl {
  ReferenceOptions opt;
  Environment env;
  Vec2 ref;
  double thickness = 0.001;
  std::vector<double> theta;            // mounting angles
  std::vector<double> wing_area, wing_span;
  double wing_span_max = 1.0;
  std::vector<Panel> panels;
  std::vector<StripInternal> strips;
  std::vector<TipSegment> segments;
  std::vector<ReferenceStrip> strips_public;
  // grid
  std::vector<double> phi_nodes;        // wake angles [rad]
  std::vector<double> ih_nodes;         // inverse heights [1/m], ascending, first 0 (no ground)
  std::vector<Node> nodes;              // index iphi * nh + ih
  double h_min = 0.01;
  FuselageTable fus;
  double plate_added_mass = 0;
  mutable std::atomic<long> unconverged{0};

  // effect factors
  double f_pd = 0, f_dw = 0, f_fs = 0, f_fd = 0, f_ge = 0, f_am = 0;
  double vortex_factor = 0;  // edge-vortex lift: options.vortex_lift x finite_span

  void build_geometry(const Glider& g);
  void build_fuselage(const Glider& g);
  double influence(const Target& t, const Panel& s, int part, double phi, double h) const;
  Eigen::MatrixXd assemble(int part, double phi, double h) const;
  Eigen::MatrixXd assemble_node(double phi, double h) const;  // h <= 0: no ground
  Eigen::MatrixXd segment_rows(double phi, double h) const;
  Node solve_node(const Eigen::MatrixXd& A, double phi, double h) const;
  void build_nodes();
  void weights(double phi, double h, int idx[4], double wt[4]) const;
  void compute(const FlightState& s, ReferenceLoads* out, Vec2* force_body, double* moment) const;
};

// ------------------------------------------------------------- geometry

void ReferenceAero::Impl::build_geometry(const Glider& g) {
  const int ns = std::max(1, opt.span_panels), nc = std::max(1, opt.chord_panels);
  for (std::size_t j = 0; j < g.wings.size(); ++j) {
    const Wing& w = g.wings[j];
    const double th = deg2rad(w.mount.angle_deg);
    theta.push_back(th);
    const Vec2 cdir{std::cos(th), std::sin(th)}, ndir{-std::sin(th), std::cos(th)};
    const Vec2 origin = Vec2{w.mount.x_m, w.mount.y_m} - ref;
    auto body = [&](double xw) { return origin + xw * cdir; };
    double zmax = 0;
    for (const auto& p : w.outline) zmax = std::max(zmax, p.y);
    const double area = std::abs(signed_area(w.outline));
    wing_area.push_back(area);
    wing_span.push_back(2 * zmax);
    if (!(zmax > 0) || !(area > 0)) throw InputError("wing '" + w.name + "' has no span");
    const double aspect = 4 * zmax * zmax / area;
    const double cn90 = opt.section.normal_force_90 +
                        f_fs * (normal_force_90(aspect) - opt.section.normal_force_90);
    const double cmean = area / (2 * zmax);
    std::vector<double> zs(ns + 1);
    for (int k = 0; k <= ns; ++k) zs[k] = zmax * std::sin(0.5 * kPi * k / ns);
    zs[ns] = zmax;
    const double eps = 1e-9 * zmax;
    for (int k = 0; k < ns; ++k) {
      const double za = zs[k], zb = zs[k + 1], zm = 0.5 * (za + zb);
      const auto im = chord_intervals(w.outline, zm);
      if (im.empty()) continue;
      auto ia = chord_intervals(w.outline, za + eps), ib = chord_intervals(w.outline, zb - eps);
      const bool trapezoids = ia.size() == im.size() && ib.size() == im.size();
      if (!trapezoids) ia = ib = im;
      for (std::size_t p = 0; p < im.size(); ++p) {
        const double xle_a = ia[p].second, xte_a = ia[p].first;
        const double xle_b = ib[p].second, xte_b = ib[p].first;
        const double ca = xle_a - xte_a, cb = xle_b - xte_b;
        const double cm = 0.5 * (ca + cb);
        if (!(cm > 1e-9)) continue;
        StripInternal st;
        st.geo.wing = static_cast<int>(j);
        st.geo.z0 = za;
        st.geo.z1 = zb;
        st.geo.chord = cm;
        st.geo.area = 2 * cm * (zb - za);
        const double xle_m = 0.5 * (xle_a + xle_b);
        st.geo.leading_edge = body(xle_m);
        st.geo.panel_begin = static_cast<int>(panels.size());
        st.n = ndir;
        st.c = cdir;
        st.p34 = body(xle_m - 0.75 * cm);
        st.pmid = body(xle_m - 0.5 * cm);
        st.cn90 = cn90;
        st.t_over_c = thickness / cm;
        // Apparent mass of a plate strip accelerating normal to itself
        // (2D: rho pi (c/2)^2 per unit span) and its rotary inertia about
        // mid-chord (rho pi (c/2)^4 / 8 per unit span), both halves.
        st.added_mass = env.air_density * kPi * cm * cm / 4 * 2 * (zb - za);
        st.added_inertia = env.air_density * kPi * std::pow(cm, 4) / 128 * 2 * (zb - za);
        const int strip_index = static_cast<int>(strips.size());
        for (int m = 0; m < nc; ++m) {
          const double fb = (m + 0.25) / nc, fc = (m + 0.75) / nc;
          Panel pn;
          pn.strip = strip_index;
          pn.wing = static_cast<int>(j);
          const Vec2 a2 = body(xle_a - fb * ca), b2 = body(xle_b - fb * cb);
          pn.a = {a2.x, a2.y, za};
          pn.b = {b2.x, b2.y, zb};
          const Vec2 c2 = body(xle_m - fc * cm);
          pn.cp = {c2.x, c2.y, zm};
          pn.normal = {ndir.x, ndir.y, 0.0};
          pn.bound_mid = body(xle_m - fb * cm);
          pn.s_bound = fb * cm;
          pn.rc = std::max(0.05 * cmean, 0.5 * (zb - za));
          panels.push_back(pn);
        }
        st.geo.panel_end = static_cast<int>(panels.size());
        st.sweep = std::atan2(xle_a - xle_b, zb - za);
        if (k == ns - 1) {
          // Side edge at the tip: segments between successive bound vortices
          // of the tip strip, the last one to the trailing edge.
          for (int m = 0; m < nc; ++m) {
            const Panel& pm = panels[st.geo.panel_begin + m];
            const Vec2 te = body(xte_b);
            const V3 end = m + 1 < nc ? panels[st.geo.panel_begin + m + 1].b : V3{te.x, te.y, zb};
            TipSegment sg;
            sg.strip = strip_index;
            sg.first_panel = st.geo.panel_begin;
            sg.panels = m + 1;
            sg.mid = 0.5 * (pm.b + end);
            sg.normal = ndir;
            sg.length = norm(end - pm.b);
            if (sg.length > 1e-12) segments.push_back(sg);
          }
        }
        strips.push_back(st);
        strips_public.push_back(st.geo);
        plate_added_mass += st.added_mass;
      }
    }
  }
  if (strips.empty()) throw InputError("the glider has no wing area for the reference simulator");
  wing_span_max = *std::max_element(wing_span.begin(), wing_span.end());
}

// Friction of the fuselage plate: for each flow direction psi (direction the
// air moves relative to the glider), the plate is cut into streamwise strips;
// a strip of streamwise length l carries laminar Blasius friction
// 1.328 sqrt(rho mu V^3 l) per unit width on both faces. Its edges carry
// pressure drag edge_drag x thickness x frontal width.
void ReferenceAero::Impl::build_fuselage(const Glider& g) {
  if (g.fuselage.size() < 3 || !(std::abs(signed_area(g.fuselage)) > 0)) return;
  fus.present = true;
  fus.n = 180;
  fus.k_f.assign(fus.n, 0);
  fus.n_f.assign(fus.n, 0);
  fus.w_e.assign(fus.n, 0);
  fus.n_e.assign(fus.n, 0);
  Polygon poly;
  for (const auto& p : g.fuselage) poly.push_back(p - ref);
  const int slices = 200;
  for (int k = 0; k < fus.n; ++k) {
    const double psi = kTwoPi * k / fus.n;
    const Vec2 e{std::cos(psi), std::sin(psi)}, ep{-std::sin(psi), std::cos(psi)};
    // polygon in (s, n) coordinates: s = p.e streamwise, n = p.e_perp
    Polygon q;
    double nmin = 1e300, nmax = -1e300;
    for (const auto& p : poly) {
      q.push_back({dot(p, e), dot(p, ep)});
      nmin = std::min(nmin, dot(p, ep));
      nmax = std::max(nmax, dot(p, ep));
    }
    const double dn = (nmax - nmin) / slices;
    for (int i = 0; i < slices; ++i) {
      const double nn = nmin + (i + 0.5) * dn;
      // intervals in s along the line n = nn (chord_intervals works on (x, z) = (s, n))
      for (const auto& iv : chord_intervals(q, nn)) {
        const double l = iv.second - iv.first;
        fus.k_f[k] += std::sqrt(l) * dn;
        fus.n_f[k] += nn * std::sqrt(l) * dn;
        fus.w_e[k] += dn;
        fus.n_e[k] += nn * dn;
      }
    }
  }
}

// Influence matrices (normal velocity at the control points per unit
// circulation), by part: `self` = each wing on itself (2D strips blended with
// the 3D lattice by finite_span), `cross` = wings on each other with the wakes
// at angle phi, `image` = the ground images at height h (own wing, plus the
// other wings when downwash is on). The node matrix is
// self + f_dw cross(phi) + f_ge image(h).
double ReferenceAero::Impl::influence(const Target& t, const Panel& s, int part, double phi, double h) const {
  const double tiny = 1e-7 * wing_span_max;
  const bool same_wing = s.wing == t.wing, same_strip = s.strip == t.strip;
  auto v2d = [&](Vec2 src, double sign) {
    const double rx = t.p.x - src.x, ry = t.p.y - src.y;
    const double r2 = rx * rx + ry * ry;
    return sign * (-ry * t.normal.x + rx * t.normal.y) / (kTwoPi * r2);
  };
  auto reflect = [h](V3 p) { return V3{p.x, -2 * h - p.y, p.z}; };
  // Side-edge targets (strip -1) see the full 3D lattice of their own wing.
  const double fs = t.strip < 0 ? 1.0 : f_fs;
  if (part == 0) {
    if (!same_wing) return 0.0;
    const double th = theta[s.wing];
    const V3 dself{-std::cos(th), -std::sin(th), 0.0};
    const double v3 = fs == 0 ? 0.0 : dot(symmetric_horseshoe(t.p, s.a, s.b, dself, tiny, tiny), t.normal);
    const double v2 = same_strip ? v2d(s.bound_mid, 1.0) : 0.0;
    return v2 + fs * (v3 - v2);
  }
  if (part == 1) {
    if (same_wing) return 0.0;
    const V3 dphi{-std::cos(phi), std::sin(phi), 0.0};
    return dot(symmetric_horseshoe(t.p, s.a, s.b, dphi, s.rc, s.rc), t.normal);
  }
  if (!same_wing && f_dw == 0) return 0.0;
  // Image system in the ground: endpoints reflected, strength negated.
  const V3 dimg{-1.0, 0.0, 0.0};
  const double v3 = (same_wing && fs == 0)
                        ? 0.0
                        : -dot(symmetric_horseshoe(t.p, reflect(s.a), reflect(s.b), dimg, s.rc, s.rc), t.normal);
  if (!same_wing) return f_dw * v3;
  const double v2 = same_strip ? v2d({s.bound_mid.x, -2 * h - s.bound_mid.y}, -1.0) : 0.0;
  return v2 + fs * (v3 - v2);
}

Eigen::MatrixXd ReferenceAero::Impl::assemble(int part, double phi, double h) const {
  const int n = static_cast<int>(panels.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    const Target t{panels[k].cp, panels[k].normal, panels[k].wing, panels[k].strip};
    for (int j = 0; j < n; ++j) A(k, j) = influence(t, panels[j], part, phi, h);
  }
  return A;
}

Eigen::MatrixXd ReferenceAero::Impl::segment_rows(double phi, double h) const {
  const int n = static_cast<int>(panels.size()), m = static_cast<int>(segments.size());
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(m, n);
  for (int k = 0; k < m; ++k) {
    const TipSegment& sg = segments[k];
    const Target t{sg.mid, {sg.normal.x, sg.normal.y, 0.0}, strips[sg.strip].geo.wing, -1};
    for (int j = 0; j < n; ++j) {
      double v = influence(t, panels[j], 0, 0, 0);
      if (phi_nodes.size() > 1) v += f_dw * influence(t, panels[j], 1, phi, 0);
      if (h > 0 && f_ge != 0) v += f_ge * influence(t, panels[j], 2, 0, h);
      W(k, j) = v;
    }
  }
  return W;
}

Eigen::MatrixXd ReferenceAero::Impl::assemble_node(double phi, double h) const {
  Eigen::MatrixXd A = assemble(0, 0, 0);
  if (phi_nodes.size() > 1) A += f_dw * assemble(1, phi, 0);
  if (h > 0 && f_ge != 0) A += f_ge * assemble(2, 0, h);
  return A;
}

Node ReferenceAero::Impl::solve_node(const Eigen::MatrixXd& A, double phi, double h) const {
  const int n = static_cast<int>(panels.size()), ns = static_cast<int>(strips.size());
  // Right-hand sides: A Gamma = -U_n with U_n = -(v_p . n) the air's normal
  // velocity at the control point, v_p = (u - q r_y, w + q r_x):
  // columns n_x (u), n_y (w), r_x n_y - r_y n_x (q), and +1 on the panels of
  // strip i (decambering: U_n -> U_n - V delta_i, per unit speed).
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, 3 + ns);
  for (int k = 0; k < n; ++k) {
    const Panel& p = panels[k];
    B(k, 0) = p.normal.x;
    B(k, 1) = p.normal.y;
    B(k, 2) = p.cp.x * p.normal.y - p.cp.y * p.normal.x;
    B(k, 3 + p.strip) = 1.0;
  }
  const Eigen::MatrixXd X = A.partialPivLu().solve(B);
  // Strip reductions: c~_i V = (2 / c_i) sum Gamma_k; cm_i V = -(2 / c_i^2) sum Gamma_k (s_k - c_i / 4).
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(ns, n), R = Eigen::MatrixXd::Zero(ns, n);
  for (int k = 0; k < n; ++k) {
    const Panel& p = panels[k];
    const double c = strips[p.strip].geo.chord;
    T(p.strip, k) = 2.0 / c;
    R(p.strip, k) = -2.0 * (p.s_bound - 0.25 * c) / (c * c);
  }
  const Eigen::MatrixXd C = T * X, M = R * X;
  Node nd;
  nd.cu = C.col(0);
  nd.cw = C.col(1);
  nd.cq = C.col(2);
  nd.cd = C.rightCols(ns);
  nd.mu = M.col(0);
  nd.mw = M.col(1);
  // The discrete 1/4-3/4 lattice gives (1 - 1/n_c^2) of the thin-airfoil
  // camber moment of a linear normal-wash variation (the pitch rate's
  // -(pi/8) omega c / V about the quarter chord); corrected here.
  const int nc = std::max(1, opt.chord_panels);
  nd.mq = M.col(2) * (nc > 1 ? 1.0 / (1.0 - 1.0 / (nc * nc)) : 1.0);
  nd.md = M.rightCols(ns);
  if (!segments.empty() && vortex_factor != 0) {
    const int m = static_cast<int>(segments.size());
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(m, n);
    for (int k = 0; k < m; ++k)
      for (int j = 0; j < segments[k].panels; ++j) G(k, segments[k].first_panel + j) = 1.0;
    nd.gs = G * X;
    nd.ws = segment_rows(phi, h) * X;
  }
  return nd;
}

void ReferenceAero::Impl::build_nodes() {
  // Wake angle grid only when wings see each other.
  std::set<int> wings;
  for (const auto& p : panels) wings.insert(p.wing);
  phi_nodes.clear();
  if (f_dw != 0 && wings.size() > 1) {
    const double lo = deg2rad(opt.wake_angle_min_deg), hi = deg2rad(opt.wake_angle_max_deg);
    const double st = deg2rad(std::max(0.5, opt.wake_angle_step_deg));
    const int n = std::max(1, static_cast<int>(std::round((hi - lo) / st)));
    for (int i = 0; i <= n; ++i) phi_nodes.push_back(lo + (hi - lo) * i / n);
  } else {
    phi_nodes.push_back(0.0);
  }
  ih_nodes = {0.0};
  double cmax = 0, bmax = 0;
  for (const auto& s : strips) cmax = std::max(cmax, s.geo.chord);
  for (double b : wing_span) bmax = std::max(bmax, b);
  double ymax = 0;
  for (const auto& p : panels) ymax = std::max({ymax, std::abs(p.cp.y), std::abs(p.a.y), std::abs(p.b.y)});
  h_min = 0.5 * cmax + ymax;
  if (f_ge != 0) {
    const double h_max = std::max(opt.ground_height_max_spans * bmax, 2 * h_min);
    const int nh = std::max(2, opt.ground_heights);
    for (int i = 0; i < nh; ++i) {
      // geometric from h_max down to h_min
      const double h = h_max * std::pow(h_min / h_max, static_cast<double>(i) / (nh - 1));
      ih_nodes.push_back(1.0 / h);
    }
  }
  nodes.clear();
  const Eigen::MatrixXd self = assemble(0, 0, 0);
  std::vector<Eigen::MatrixXd> images;
  for (double ih : ih_nodes) images.push_back(ih > 0 ? Eigen::MatrixXd(f_ge * assemble(2, 0, 1.0 / ih)) : Eigen::MatrixXd());
  for (double phi : phi_nodes) {
    Eigen::MatrixXd base = self;
    if (phi_nodes.size() > 1) base += f_dw * assemble(1, phi, 0);
    for (std::size_t i = 0; i < ih_nodes.size(); ++i)
      nodes.push_back(solve_node(ih_nodes[i] > 0 ? Eigen::MatrixXd(base + images[i]) : base, phi,
                                  ih_nodes[i] > 0 ? 1.0 / ih_nodes[i] : 0.0));
  }
}

void ReferenceAero::Impl::weights(double phi, double h, int idx[4], double wt[4]) const {
  const int np = static_cast<int>(phi_nodes.size()), nh = static_cast<int>(ih_nodes.size());
  int ip = 0;
  double fp = 0;
  if (np > 1) {
    const double lo = phi_nodes.front(), hi = phi_nodes.back();
    const double x = (std::clamp(phi, lo, hi) - lo) / (hi - lo) * (np - 1);
    ip = std::min(np - 2, static_cast<int>(std::floor(x)));
    fp = x - ip;
  }
  int ih = 0;
  double fh = 0;
  if (nh > 1) {
    const double inv = h > 0 ? std::min(1.0 / std::max(h, h_min), ih_nodes.back()) : ih_nodes.back();
    while (ih < nh - 2 && inv > ih_nodes[ih + 1]) ++ih;
    fh = (inv - ih_nodes[ih]) / (ih_nodes[ih + 1] - ih_nodes[ih]);
    fh = std::clamp(fh, 0.0, 1.0);
  }
  const int ip1 = np > 1 ? ip + 1 : ip, ih1 = nh > 1 ? ih + 1 : ih;
  idx[0] = ip * nh + ih;
  idx[1] = ip * nh + ih1;
  idx[2] = ip1 * nh + ih;
  idx[3] = ip1 * nh + ih1;
  wt[0] = (1 - fp) * (1 - fh);
  wt[1] = (1 - fp) * fh;
  wt[2] = fp * (1 - fh);
  wt[3] = fp * fh;
}

// ------------------------------------------------------------ evaluation

void ReferenceAero::Impl::compute(const FlightState& s, ReferenceLoads* out, Vec2* force_body,
                                  double* moment) const {
  const int ns = static_cast<int>(strips.size());
  const std::size_t nw = theta.size();
  if (out) {
    out->wing_force.assign(nw, {});
    out->wing_moment.assign(nw, 0.0);
    out->strip_alpha_eff.assign(ns, 0.0);
    out->strip_cn.assign(ns, 0.0);
  }
  *force_body = {};
  *moment = 0;
  const Vec2 vb = rotate(s.v, -s.beta);  // glider velocity relative to the air, glider frame
  const double V = norm(vb);
  if (!(V > 1e-9)) return;
  const double u = vb.x, w = vb.y;
  const double q = f_pd * s.omega;
  const double rho = env.air_density, mu = env.air_viscosity;
  const double qinf = 0.5 * rho * V * V;
  const double gamma = std::atan2(-w, u);

  int idx[4];
  double wt[4];
  weights(gamma, s.p.y, idx, wt);
  Scratch& sc0 = scratch(ns);
  Eigen::VectorXd &c0 = sc0.c0, &m0 = sc0.m0;
  Eigen::MatrixXd &CD = sc0.CD, &MD = sc0.MD;
  c0.setZero();
  m0.setZero();
  CD.setZero();
  MD.setZero();
  for (int k = 0; k < 4; ++k) {
    if (wt[k] == 0) continue;
    const Node& nd = nodes[idx[k]];
    c0.noalias() += (wt[k] / V) * (u * nd.cu + w * nd.cw + q * nd.cq);
    m0.noalias() += (wt[k] / V) * (u * nd.mu + w * nd.mw + q * nd.mq);
    CD.noalias() += wt[k] * nd.cd;
    MD.noalias() += wt[k] * nd.md;
  }
  // Normalised normal (n) and tangential (t, from the leading edge) air
  // velocity at each strip's 3/4-chord point; the geometric angle of attack
  // there and the separated-flow force term, which uses the 3D finite-plate
  // law at the geometric angle (it already holds the finite-span reduction,
  // so it is not given the lattice's induced angle again).
  Scratch& sc = scratch(ns);
  Eigen::VectorXd &nn = sc.nn, &tt = sc.tt, &gsep = sc.gsep;
  for (int i = 0; i < ns; ++i) {
    const StripInternal& st = strips[i];
    const Vec2 vp{u - q * st.p34.y, w + q * st.p34.x};
    nn(i) = -dot(vp, st.n) / V;
    tt(i) = dot(vp, st.c) / V;
    gsep(i) = (nn(i) * nn(i) + tt(i) * tt(i)) *
              opt.section.separated_normal_force(std::atan2(nn(i), tt(i)), st.cn90);
  }
  // Decambering: c~ = c0 + CD delta; the normalised induced normal velocity
  // w = n - delta - c~ / 2 pi = w0 - K delta. Find w such that the lattice
  // carries the 2D section's force, c~ = g(w) = ((n - w)^2 + t^2) c_n(a_e),
  // a_e = atan2(n - w, t). The 2D law is monotone in a_e, so the solution is
  // unique (no saw-tooth or branch jumps past stall).
  const Eigen::VectorXd& w0 = sc.w0 = nn - c0 / kTwoPi;
  Eigen::MatrixXd& K = sc.K;
  K.noalias() = CD / kTwoPi;
  K.diagonal().array() += 1.0;
  Eigen::VectorXd &wi = sc.wi, &g = sc.g, &dg = sc.dg, &delta = sc.delta, &F = sc.F, &F2 = sc.F2,
                  &w2 = sc.w2, &step = sc.step;
  wi = w0;
  const SectionLaw& law = opt.section;
  const double cn90_2d = law.normal_force_90;
  auto evalg = [&](const Eigen::VectorXd& wv, bool deriv) {
    for (int i = 0; i < ns; ++i) {
      const double sn = nn(i) - wv(i), t = tt(i);
      const double a = std::atan2(sn, t);
      double dcn = 0;
      const double cn = law.normal_force(a, cn90_2d, deriv ? &dcn : nullptr);
      g(i) = (sn * sn + t * t) * cn;
      if (deriv) dg(i) = -(2 * sn * cn + t * dcn);  // dg/dw
    }
  };
  auto residual = [&](const Eigen::VectorXd& wv, Eigen::VectorXd& out) {
    evalg(wv, false);
    delta = nn - wv - g / kTwoPi;
    out.noalias() = w0 - wv;
    out.noalias() -= K * delta;
  };
  residual(wi, F);
  double fn = F.lpNorm<Eigen::Infinity>();
  int it = 0;
  bool conv = fn < opt.tolerance;
  while (!conv && it < opt.max_iterations) {
    ++it;
    evalg(wi, true);
    // J = dF/dw = K diag(1 + g'/2pi) - I
    sc.J.noalias() = K * (Eigen::VectorXd::Ones(ns) + dg / kTwoPi).asDiagonal();
    sc.J.diagonal().array() -= 1.0;
    sc.lu.compute(sc.J);
    step.noalias() = sc.lu.solve(-F);
    if (!step.allFinite()) step = F;  // fixed-point step
    double lam = 1.0;
    bool accepted = false;
    for (int h = 0; h < 12; ++h, lam *= 0.5) {
      w2 = wi + lam * step;
      residual(w2, F2);
      const double f2 = F2.lpNorm<Eigen::Infinity>();
      if (f2 < (1 - 1e-4 * lam) * fn || f2 < opt.tolerance) {
        wi.swap(w2);
        F.swap(F2);
        fn = f2;
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      // Damped fixed-point step as a last resort.
      wi += 0.25 * F;
      residual(wi, F);
      fn = F.lpNorm<Eigen::Infinity>();
    }
    conv = fn < opt.tolerance;
  }
  if (!conv && fn > 1e-6) unconverged.fetch_add(1, std::memory_order_relaxed);
  residual(wi, F);  // g and delta at the final w
  const Eigen::VectorXd cm = m0 + MD * delta;
  if (out) {
    out->iterations = it;
    out->converged = conv || fn <= 1e-6;
  }

  // Strip forces (both halves).
  Vec2 F_b{};
  double M = 0;
  for (int i = 0; i < ns; ++i) {
    const StripInternal& st = strips[i];
    const double sn = nn(i) - wi(i), t = tt(i);
    const double ve2 = sn * sn + t * t;
    const double a = std::atan2(sn, t);
    const double ag = std::atan2(nn(i), t);
    const double f = law.attached_fraction(a);
    const double n_att = ve2 * f * law.attached_normal_force(a);  // per q_inf
    const double n_sep = (1 - f) * gsep(i);
    const double S = st.geo.area, c = st.geo.chord;
    const double N = qinf * S * (n_att + n_sep);
    const double vt = V * std::abs(t);
    const double re_t = rho * vt * c / mu;
    const double T = -(t < 0 ? -1.0 : 1.0) * 0.5 * rho * vt * vt * S *
                     (law.friction(re_t) + law.edge_drag * st.t_over_c);
    const double x_att = std::cos(a) >= 0 ? 0.25 : 0.75;
    const double x_sep = 0.5 - 0.25 * std::cos(ag);
    const double wsum = std::abs(n_att) + std::abs(n_sep);
    const double xcp = wsum > 1e-300 ? (std::abs(n_att) * x_att + std::abs(n_sep) * x_sep) / wsum : x_att;
    const Vec2 rcp = st.geo.leading_edge - (xcp * c) * st.c;
    const Vec2 fN = N * st.n, fT = T * st.c;
    const double Mi = cross(rcp, fN) + cross(st.pmid, fT) + qinf * S * c * cm(i) * f;
    const Vec2 Fi = fN + fT;
    F_b = F_b + Fi;
    M += Mi;
    if (out) {
      out->wing_force[st.geo.wing] = out->wing_force[st.geo.wing] + Fi;
      out->wing_moment[st.geo.wing] += Mi;
      out->strip_alpha_eff[i] = a;
      out->strip_cn[i] = ve2 > 1e-300 ? (n_att + n_sep) / ve2 : 0.0;
    }
  }
  // Edge-vortex lift from the linear (potential) lattice solution, as in the
  // suction analogies. Leading edges (Polhamus 1966): a strip's potential
  // leading-edge suction c0 (n - w0) (per q_inf), turned normal to the plate
  // and divided by cos(sweep), for swept edges only (weight 0 below
  // le_vortex_sweep_deg[0], 1 above [1], smoothstep between). Side edges
  // (Lamar 1974): the Kutta-Joukowski force rho G |U_n| l of the tip strip's
  // trailing legs that run along the tip, turned normal to the plate. Both
  // vanish past vortex breakdown: factor 1 / (1 + exp((|a_g| - a_b) / w_b)) of
  // the strip's geometric angle of attack.
  if (vortex_factor != 0) {
    const double s0 = deg2rad(opt.le_vortex_sweep_deg[0]), s1 = deg2rad(opt.le_vortex_sweep_deg[1]);
    const double ab = deg2rad(opt.vortex_breakdown_deg[0]), wb = deg2rad(opt.vortex_breakdown_deg[1]);
    auto burst = [&](int i) {
      double ag = std::abs(std::atan2(nn(i), tt(i)));
      ag = std::min(ag, kPi - ag);
      return 1.0 / (1.0 + std::exp((ag - ab) / wb));
    };
    auto add = [&](int wing, Vec2 where, double n_force, Vec2 normal) {
      const Vec2 fv = n_force * normal;
      F_b = F_b + fv;
      M += cross(where, fv);
      if (out) {
        out->wing_force[wing] = out->wing_force[wing] + fv;
        out->wing_moment[wing] += cross(where, fv);
        out->vortex_normal_force += n_force;
      }
    };
    for (int i = 0; i < ns; ++i) {
      const StripInternal& st = strips[i];
      const double sw = std::abs(st.sweep);
      if (sw <= s0) continue;
      const double u01 = std::clamp((sw - s0) / std::max(1e-9, s1 - s0), 0.0, 1.0);
      const double wle = u01 * u01 * (3 - 2 * u01);
      const double dn = vortex_factor * wle * burst(i) * c0(i) * std::abs(nn(i) - w0(i)) / std::cos(st.sweep);
      add(st.geo.wing, st.geo.leading_edge, qinf * st.geo.area * dn, st.n);
    }
    const int nseg = static_cast<int>(segments.size());
    if (nseg > 0) {
      Eigen::VectorXd xi = Eigen::VectorXd::Zero(3 + ns);
      xi(0) = u;
      xi(1) = w;
      xi(2) = q;
      Eigen::VectorXd G = Eigen::VectorXd::Zero(nseg), W = Eigen::VectorXd::Zero(nseg);
      for (int k = 0; k < 4; ++k) {
        if (wt[k] == 0) continue;
        G.noalias() += wt[k] * (nodes[idx[k]].gs * xi);
        W.noalias() += wt[k] * (nodes[idx[k]].ws * xi);
      }
      for (int k = 0; k < nseg; ++k) {
        const TipSegment& sg = segments[k];
        const Vec2 vp{u - q * sg.mid.y, w + q * sg.mid.x};
        const double un = -dot(vp, sg.normal) + W(k);
        // both tips
        const double dn = vortex_factor * burst(sg.strip) * 2 * rho * G(k) * std::abs(un) * sg.length;
        add(strips[sg.strip].geo.wing, {sg.mid.x, sg.mid.y}, dn, sg.normal);
      }
    }
  }
  // Fuselage plate: friction along the air flow over it, edge pressure drag.
  if (fus.present && f_fd != 0) {
    const Vec2 e{-u / V, -w / V};  // direction the air moves relative to the glider
    double psi = std::atan2(e.y, e.x);
    if (psi < 0) psi += kTwoPi;
    const double x = psi / kTwoPi * fus.n;
    const int i0 = static_cast<int>(std::floor(x)) % fus.n, i1 = (i0 + 1) % fus.n;
    const double fr = x - std::floor(x);
    auto lerp = [&](const std::vector<double>& v) { return (1 - fr) * v[i0] + fr * v[i1]; };
    const double kf = 1.328 * std::sqrt(rho * mu * V * V * V);
    const double ke = qinf * opt.section.edge_drag * thickness;
    const double D = f_fd * (kf * lerp(fus.k_f) + ke * lerp(fus.w_e));
    const double Mf = -f_fd * (kf * lerp(fus.n_f) + ke * lerp(fus.n_e));
    const Vec2 Ff = D * e;
    F_b = F_b + Ff;
    M += Mf;
    if (out) {
      out->fuselage_force = Ff;
      out->fuselage_moment = Mf;
    }
  }
  *force_body = F_b;
  *moment = M;
  if (out) {
    out->force_body = F_b;
    out->moment = M;
  }
}

// ------------------------------------------------------------ public API

ReferenceAero::ReferenceAero(const Glider& g, const ReferenceOptions& opt, const Environment& env)
    : ReferenceAero(g, mass_properties(g).cg, opt, env) {}

ReferenceAero::ReferenceAero(const Glider& g, Vec2 reference, const ReferenceOptions& opt,
                             const Environment& env)
    : impl_(std::make_unique<Impl>()) {
  if (opt.span_panels < 1 || opt.span_panels > 200 || opt.chord_panels < 1 || opt.chord_panels > 50)
    throw InputError("reference simulator: panel counts must be 1-200 spanwise and 1-50 chordwise");
  if (g.wings.empty()) throw InputError("the glider has no wings");
  for (const char* n : {"pitch_damping", "downwash", "finite_span", "fuselage_drag", "ground_effect",
                        "added_mass"}) {
    const double f = opt.effects[n].factor();
    if (!std::isfinite(f) || f < 0 || f > 10)
      throw InputError(std::string("strength of effect '") + n + "' must be between 0 and 10");
  }
  Impl& m = *impl_;
  m.opt = opt;
  m.env = env;
  m.ref = reference;
  m.thickness = g.material.thickness_m;
  m.f_pd = opt.effects.pitch_damping.factor();
  m.f_dw = opt.effects.downwash.factor();
  m.f_fs = opt.effects.finite_span.factor();
  m.f_fd = opt.effects.fuselage_drag.factor();
  m.f_ge = opt.effects.ground_effect.factor();
  m.f_am = opt.effects.added_mass.factor();
  m.vortex_factor = opt.vortex_lift * m.f_fs;
  m.build_geometry(g);
  m.build_fuselage(g);
  m.build_nodes();
}

ReferenceAero::~ReferenceAero() = default;

Wrench ReferenceAero::evaluate(const FlightState& s) const {
  Vec2 fb;
  double mz;
  impl_->compute(s, nullptr, &fb, &mz);
  return {rotate(fb, s.beta), mz};
}

ReferenceLoads ReferenceAero::loads(const FlightState& s) const {
  ReferenceLoads out;
  Vec2 fb;
  double mz;
  impl_->compute(s, &out, &fb, &mz);
  return out;
}

GliderForces ReferenceAero::forces(double v, double gamma, double omega, double height) const {
  FlightState s;
  s.v = {v, 0.0};
  s.beta = gamma;
  s.omega = omega;
  s.p = {0.0, height};
  const Wrench w = evaluate(s);
  return {-w.force.x, w.force.y, w.moment};
}

double ReferenceAero::max_alpha(const FlightState& s) const {
  const double g = angle_of_attack(s);
  double m = 0;
  for (double th : impl_->theta) m = std::max(m, std::abs(wrap(g + th)));
  return m;
}

double ReferenceAero::alpha_limit() const { return deg2rad(impl_->opt.alpha_limit_deg); }

bool ReferenceAero::has_added_mass() const { return impl_->f_am != 0; }

AddedMass ReferenceAero::added_mass(const FlightState& s) const {
  // Non-circulatory force of each strip: -m_a dv_n/dt normal to the plate at
  // mid-chord, with v_n = n . (v + omega z x r) and
  // dv_n/dt = J . (x'', y'', beta'') + omega (z x n) . v; rotary term -I_a beta''.
  AddedMass am;
  const Impl& m = *impl_;
  if (m.f_am == 0) return am;
  const Vec2 vb = rotate(s.v, -s.beta);
  for (const auto& st : m.strips) {
    const double ma = m.f_am * st.added_mass;
    const Vec2 nw = rotate(st.n, s.beta);
    const double J[3] = {nw.x, nw.y, st.pmid.x * st.n.y - st.pmid.y * st.n.x};
    const double c = s.omega * (-st.n.y * vb.x + st.n.x * vb.y);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) am.m[a][b] += ma * J[a] * J[b];
      am.bias[a] -= ma * c * J[a];
    }
    am.m[2][2] += m.f_am * st.added_inertia;
  }
  return am;
}

PotentialSolution ReferenceAero::potential(double gamma) const {
  const Impl& m = *impl_;
  const double phi = m.phi_nodes.size() > 1
                         ? std::clamp(gamma, m.phi_nodes.front(), m.phi_nodes.back())
                         : 0.0;
  const Eigen::MatrixXd A = m.assemble_node(phi, 0.0);
  const int n = static_cast<int>(m.panels.size()), ns = static_cast<int>(m.strips.size());
  Eigen::VectorXd rhs(n);
  const double u = std::cos(gamma), w = -std::sin(gamma);
  for (int k = 0; k < n; ++k) rhs(k) = u * m.panels[k].normal.x + w * m.panels[k].normal.y;
  const Eigen::VectorXd G = A.partialPivLu().solve(rhs);
  PotentialSolution out;
  for (double a : m.wing_area) out.area += a;
  for (double b : m.wing_span) out.span = std::max(out.span, b);
  std::vector<double> gs(ns, 0.0);
  for (int k = 0; k < n; ++k) gs[m.panels[k].strip] += G(k);
  double lift = 0;
  for (int i = 0; i < ns; ++i) lift += gs[i] * (m.strips[i].geo.z1 - m.strips[i].geo.z0);
  // L = rho V int Gamma dz over the full span; V = 1.
  out.cl = 4 * lift / out.area;
  // Trefftz plane. A single wing with one piece per station: fit the
  // symmetric sine series Gamma(theta) = sum_{n odd} a_n sin(n theta),
  // z = -(b/2) cos(theta), at the strip mid-angles; span efficiency
  // e = a_1^2 / sum n a_n^2 and C_Di = C_L^2 / (pi A e) (lifting-line
  // theory's exact drag of that loading). Otherwise the midpoint rule over
  // the trailing legs as 2D vortices: D_i = -rho/2 int Gamma w dz.
  for (int i = 0; i < ns; ++i) {
    out.z.push_back(0.5 * (m.strips[i].geo.z0 + m.strips[i].geo.z1));
    out.gamma.push_back(gs[i]);
  }
  bool single = m.wing_area.size() == 1;
  for (int i = 1; i < ns && single; ++i) single = m.strips[i].geo.z0 >= m.strips[i - 1].geo.z1 - 1e-12;
  if (single) {
    const double half = 0.5 * m.wing_span[0];
    Eigen::MatrixXd S(ns, ns);
    Eigen::VectorXd gv(ns);
    for (int i = 0; i < ns; ++i) {
      const double ta = kPi - std::acos(std::clamp(m.strips[i].geo.z0 / half, -1.0, 1.0));
      const double tb = kPi - std::acos(std::clamp(m.strips[i].geo.z1 / half, -1.0, 1.0));
      const double th = 0.5 * (ta + tb);
      for (int k = 0; k < ns; ++k) S(i, k) = std::sin((2 * k + 1) * th);
      gv(i) = gs[i];
    }
    const Eigen::VectorXd a = S.colPivHouseholderQr().solve(gv);
    double sum = 0;
    for (int k = 0; k < ns; ++k) sum += (2 * k + 1) * a(k) * a(k);
    const double e = sum > 0 ? a(0) * a(0) / sum : 1.0;
    const double aspect = m.wing_span[0] * m.wing_span[0] / out.area;
    out.cdi = out.cl * out.cl / (kPi * aspect * e);
    return out;
  }
  double di = 0;
  for (int i = 0; i < ns; ++i) {
    const double zi = out.z[i];
    double wv = 0;
    for (int j = 0; j < ns; ++j) {
      const double z0 = m.strips[j].geo.z0, z1 = m.strips[j].geo.z1;
      auto inv = [](double d) { return std::abs(d) < 1e-12 ? 0.0 : 1.0 / d; };
      wv += gs[j] / kTwoPi * (inv(zi - z1) - inv(zi - z0) - inv(zi + z1) + inv(zi + z0));
    }
    di += gs[i] * wv * (m.strips[i].geo.z1 - m.strips[i].geo.z0);
  }
  out.cdi = -2 * di / out.area;
  return out;
}

const std::vector<ReferenceStrip>& ReferenceAero::strips() const { return impl_->strips_public; }
int ReferenceAero::panel_count() const { return static_cast<int>(impl_->panels.size()); }
int ReferenceAero::node_count() const { return static_cast<int>(impl_->nodes.size()); }
const ReferenceOptions& ReferenceAero::options() const { return impl_->opt; }
double ReferenceAero::plate_added_mass() const { return impl_->plate_added_mass; }
long ReferenceAero::unconverged_count() const { return impl_->unconverged.load(); }

}  // namespace pteromys
