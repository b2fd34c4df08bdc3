// Slotted plates: joint choice, slots, assembly order (docs/fabrication.md).
#include "pteromys/fabrication.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <set>
#include <tuple>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include "pteromys/fabrication_geometry.hpp"
#include "pteromys/geometry.hpp"
#include "pteromys/mass.hpp"

namespace pteromys {

// ------------------------------------------------------------------ names

std::string joint_type_name(JointType t) {
  switch (t) {
    case JointType::Auto: return "auto";
    case JointType::ThroughSlot: return "through_slot";
    case JointType::Notch: return "notch";
    case JointType::CrossLap: return "cross_lap";
    case JointType::Halves: return "halves";
  }
  return "auto";
}

JointType joint_type_from_name(const std::string& s) {
  if (s == "auto") return JointType::Auto;
  if (s == "through_slot" || s == "through-slot") return JointType::ThroughSlot;
  if (s == "notch") return JointType::Notch;
  if (s == "cross_lap" || s == "cross-lap") return JointType::CrossLap;
  if (s == "halves") return JointType::Halves;
  throw InputError("unknown joint type '" + s + "' (expected auto, through_slot, notch, cross_lap or halves)");
}

std::string mark_kind_name(Mark::Kind k) {
  switch (k) {
    case Mark::Kind::Line: return "line";
    case Mark::Kind::Cross: return "cross";
    case Mark::Kind::Text: return "text";
  }
  return "line";
}

namespace {

std::string num(double v, int prec = 1) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  std::string s = b;
  if (s == "-0" || s == "-0.0" || s == "-0.00") s = s.substr(1);
  return s;
}
std::string mm(double m, int prec = 1) { return num(m * 1000.0, prec); }
std::string mmv(double m) {
  // short form: 2 -> "2", 0.05 -> "0.05"
  char b[64];
  std::snprintf(b, sizeof b, "%g", m * 1000.0);
  return b;
}

}  // namespace

void check_fabrication_options(const FabricationOptions& o, double t) {
  auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(t) || t <= 0) throw InputError("sheet thickness must be a positive number (got " + mmv(t) + " mm)");
  if (t > 0.05) throw InputError("sheet thickness " + mmv(t) + " mm is not a plate (at most 50 mm)");
  if (!finite(o.kerf_m) || o.kerf_m < 0) throw InputError("kerf must be a number >= 0 mm (got " + mmv(o.kerf_m) + ")");
  if (!finite(o.clearance_m)) throw InputError("clearance must be a finite number of mm");
  if (!finite(o.min_web_m) || o.min_web_m < 0)
    throw InputError("minimum web must be a number >= 0 mm (got " + mmv(o.min_web_m) + ")");
  if (o.min_web_m > 0.1) throw InputError("minimum web " + mmv(o.min_web_m) + " mm is larger than any glider part (at most 100 mm)");
  if (!finite(o.thickness_m) || o.thickness_m < 0) throw InputError("thickness override must be a number >= 0 mm");
  if (!finite(o.text_height_m) || o.text_height_m <= 0 || o.text_height_m > 0.05)
    throw InputError("text height must be in (0, 50] mm");
  const double w = t + o.clearance_m;
  if (w <= 0.1 * t)
    throw InputError("clearance " + mmv(o.clearance_m) + " mm makes the slots " + mmv(w) + " mm wide for a " + mmv(t) +
                     " mm sheet; a press fit may be at most 90% of the thickness tighter");
  if (o.clearance_m > t)
    throw InputError("clearance " + mmv(o.clearance_m) + " mm is larger than the sheet thickness " + mmv(t) +
                     " mm; the slots would not hold the wings");
  if (o.kerf_m >= w)
    throw InputError("kerf " + mmv(o.kerf_m) + " mm is not narrower than the " + mmv(w) +
                     " mm slots; a laser this wide cannot cut them");
}

namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using EPoint = EK::Point_2;
using EPoly = CGAL::Polygon_2<EK>;
using EPwh = CGAL::Polygon_with_holes_2<EK>;
using EPset = CGAL::Polygon_set_2<EK>;

EPoly exact(const Polygon& p) {
  EPoly e;
  for (const auto& v : p) e.push_back(EPoint(v.x, v.y));
  if (e.is_clockwise_oriented()) e.reverse_orientation();
  return e;
}

Polygon to_dbl(const EPoly& e) {
  Polygon p;
  p.reserve(e.size());
  for (auto it = e.vertices_begin(); it != e.vertices_end(); ++it)
    p.push_back({CGAL::to_double(it->x()), CGAL::to_double(it->y())});
  return p;
}

/// Rectangle o + s u + h n (n = u turned +90 deg), s in [s0, s1], h in [h0, h1], ccw.
Polygon rect_pts(Vec2 o, Vec2 u, double s0, double s1, double h0, double h1) {
  const Vec2 n{-u.y, u.x};
  return {o + s0 * u + h0 * n, o + s1 * u + h0 * n, o + s1 * u + h1 * n, o + s0 * u + h1 * n};
}

struct Iv {
  double a, b;
};

std::vector<Iv> merge_iv(std::vector<Iv> v, double tol = 1e-12) {
  std::sort(v.begin(), v.end(), [](const Iv& x, const Iv& y) { return x.a < y.a; });
  std::vector<Iv> out;
  for (const auto& i : v) {
    if (i.b < i.a) continue;
    if (!out.empty() && i.a <= out.back().b + tol) out.back().b = std::max(out.back().b, i.b);
    else out.push_back(i);
  }
  return out;
}

std::vector<Iv> iv_subtract(const std::vector<Iv>& a, const std::vector<Iv>& b) {
  std::vector<Iv> out;
  for (const auto& x : a) {
    std::vector<Iv> pieces{x};
    for (const auto& y : b) {
      std::vector<Iv> next;
      for (const auto& p : pieces) {
        if (y.b <= p.a || y.a >= p.b) { next.push_back(p); continue; }
        if (y.a > p.a) next.push_back({p.a, y.a});
        if (y.b < p.b) next.push_back({y.b, p.b});
      }
      pieces = next;
    }
    out.insert(out.end(), pieces.begin(), pieces.end());
  }
  return out;
}

std::vector<Iv> iv_intersect(const std::vector<Iv>& a, const std::vector<Iv>& b) {
  std::vector<Iv> out;
  for (const auto& x : a)
    for (const auto& y : b) {
      const double lo = std::max(x.a, y.a), hi = std::min(x.b, y.b);
      if (hi > lo) out.push_back({lo, hi});
    }
  return merge_iv(out);
}

/// Intervals of dot(p - o, u) covered by region ∩ clip (exact intersection).
std::vector<Iv> project(const EPset& region, const Polygon& clip, Vec2 o, Vec2 u) {
  EPset r(region);
  r.intersection(exact(clip));
  std::vector<EPwh> pw;
  r.polygons_with_holes(std::back_inserter(pw));
  std::vector<Iv> out;
  for (const auto& p : pw) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (auto it = p.outer_boundary().vertices_begin(); it != p.outer_boundary().vertices_end(); ++it) {
      const double s = (CGAL::to_double(it->x()) - o.x) * u.x + (CGAL::to_double(it->y()) - o.y) * u.y;
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
    if (hi > lo) out.push_back({lo, hi});
  }
  return merge_iv(out);
}

std::size_t pieces(const EPset& s) { return s.number_of_polygons_with_holes(); }

/// Frame of a wing's root chord in the fuselage plane.
struct WingFrame {
  Vec2 P;  ///< mount
  Vec2 d;  ///< chord direction (cos, sin)
  double theta = 0;
};

struct Candidate {
  JointType type = JointType::Auto;
  int dir = 0;
  std::string problem;
  std::vector<Slot> fus_slots, wing_slots;
  double split = 0, ea = 0, eb = 0;
  double fus_len = 0;  ///< length of fuselage slot inside the plate (cross-lap)
  bool long_lap = false;  ///< cross-lap whose open slot is longer than the joint
  std::string note;       ///< what a person should know (a slot opened to the edge)
  std::vector<EPset> wing_parts;  ///< whole (slotted) wing, or right and left halves
};

struct Ctx {
  const Glider& g;
  const FabricationOptions& o;
  double t = 0, w = 0, R = 0;
  Polygon fus;
  EPset fus_set;
  std::vector<WingFrame> frames;
  std::vector<Polygon> wings;
  std::vector<EPset> wing_sets;

  Ctx(const Glider& gl, const FabricationOptions& op, double thickness) : g(gl), o(op), t(thickness) {
    w = t + o.clearance_m;
    double ext = 0;
    auto grow = [&](const Polygon& p) {
      for (const auto& v : p) ext = std::max({ext, std::fabs(v.x), std::fabs(v.y)});
    };
    grow(g.fuselage);
    fus = counter_clockwise(g.fuselage);
    fus_set = EPset(exact(fus));
    for (const auto& wg : g.wings) {
      grow(wg.outline);
      ext = std::max({ext, std::fabs(wg.mount.x_m), std::fabs(wg.mount.y_m)});
      WingFrame f;
      f.P = {wg.mount.x_m, wg.mount.y_m};
      f.theta = deg2rad(wg.mount.angle_deg);
      f.d = {std::cos(f.theta), std::sin(f.theta)};
      frames.push_back(f);
      wings.push_back(counter_clockwise(wg.outline));
      wing_sets.emplace_back(exact(wings.back()));
    }
    R = 4 * ext + 1.0;
  }
};

// ------------------------------------------------------------ plate checks

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string slot_words(const std::vector<Slot>& slots, const std::vector<std::size_t>& idx) {
  std::vector<std::string> names;
  for (auto i : idx)
    if (std::find(names.begin(), names.end(), slots[i].wing) == names.end()) names.push_back(slots[i].wing);
  if (names.size() == 1) return "the slot for wing " + quote(names[0]);
  std::string s = "the slots for wings ";
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i ? (i + 1 == names.size() ? " and " : ", ") : "") + quote(names[i]);
  return s;
}

struct PlateCheck {
  std::string problem;
  EPset result;
  std::vector<double> inside_len;  ///< per slot: length of the slot's axis inside the plate
};

/// First crossing of the ray a + l u (0 < l <= L) with the polygon boundary.
bool first_crossing(const Polygon& poly, Vec2 a, Vec2 u, double L, double& lam, Vec2& edge) {
  lam = std::numeric_limits<double>::infinity();
  const Vec2 b = a + L * u;
  const Vec2 ab = b - a;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 c = poly[i], d = poly[(i + 1) % poly.size()];
    const Vec2 cd = d - c;
    const double den = cross(ab, cd);
    if (std::fabs(den) < 1e-300) continue;
    const double t = cross(c - a, cd) / den, s = cross(c - a, ab) / den;
    if (t > 1e-12 && t <= 1 && s >= 0 && s <= 1 && t * L < lam) {
      lam = t * L;
      edge = cd;
    }
  }
  return std::isfinite(lam);
}

/// Closest points of segments [p, q] and [r, s]: distance, and the midpoint
/// of the two closest points in `mid`.
double segment_closest(Vec2 p, Vec2 q, Vec2 r, Vec2 s, Vec2& mid) {
  if (fab::segments_intersect(p, q, r, s)) {
    const Vec2 d1 = q - p, d2 = s - r;
    const double den = cross(d1, d2);
    mid = std::fabs(den) > 1e-300 ? p + (cross(r - p, d2) / den) * d1 : p;
    return 0.0;
  }
  auto proj = [](Vec2 x, Vec2 a, Vec2 b) {
    const Vec2 ab = b - a;
    const double L2 = dot(ab, ab);
    return L2 > 0 ? a + std::clamp(dot(x - a, ab) / L2, 0.0, 1.0) * ab : a;
  };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [x, a, b] : {std::tuple{p, r, s}, std::tuple{q, r, s}, std::tuple{r, p, q}, std::tuple{s, p, q}}) {
    const Vec2 y = proj(x, a, b);
    const double d = norm(x - y);
    if (d < best) {
      best = d;
      mid = 0.5 * (x + y);
    }
  }
  return best;
}

/// Distance between the boundaries of a and b (no containment test); `where`
/// gets the middle of the narrowest gap.
double boundary_distance(const Polygon& a, const Polygon& b, Vec2& where) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) {
      Vec2 m;
      const double d = segment_closest(a[i], a[(i + 1) % a.size()], b[j], b[(j + 1) % b.size()], m);
      if (d < best) {
        best = d;
        where = m;
      }
    }
  return best;
}

/// Cuts `slots` out of a plate and checks that it stays one piece and that
/// every slot leaves webs of at least min_web (docs/fabrication.md, "Rules").
PlateCheck check_plate(const std::string& plate_words, const std::string& coords, const Polygon& outline,
                       const EPset& plate, const std::vector<Slot>& slots, double min_web) {
  PlateCheck pc;
  pc.result = plate;
  for (const auto& s : slots) pc.result.difference(exact(s.rect));
  std::vector<std::size_t> all(slots.size());
  std::iota(all.begin(), all.end(), 0);
  if (pieces(pc.result) != 1) {
    pc.problem = slot_words(slots, all) + " would cut " + plate_words + " in two";
    return pc;
  }
  auto at = [&](Vec2 p) { return " near (" + coords + ") = (" + mm(p.x) + ", " + mm(p.y) + ") mm"; };
  pc.inside_len.assign(slots.size(), 0.0);
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const Slot& s = slots[k];
    const Vec2 u = s.axis_dir, n{-u.y, u.x};
    const double hw = s.width_m / 2;
    double inner = s.length_m;
    if (s.open) {
      if (!fab::point_in_polygon(outline, s.axis_origin)) {
        pc.problem = slot_words(slots, {k}) + " would not start inside " + plate_words + at(s.axis_origin);
        return pc;
      }
      double lam_min = std::numeric_limits<double>::infinity();
      for (double nu : {-hw, 0.0, hw}) {
        double lam;
        Vec2 e;
        if (!first_crossing(outline, s.axis_origin + nu * n, u, s.length_m, lam, e)) continue;
        lam_min = std::min(lam_min, lam);
        if (nu == 0.0) pc.inside_len[k] = lam;
        if (nu != 0.0) {
          const double phi = rad2deg(std::asin(std::min(1.0, std::fabs(cross(u, (1.0 / norm(e)) * e)))));
          if (phi < 30.0) {
            pc.problem = slot_words(slots, {k}) + " would meet the edge of " + plate_words + " at a glancing " +
                         num(phi, 0) + " degrees" + at(s.axis_origin + lam * u + nu * n) +
                         ", leaving a sliver (slots must cross an edge at 30 degrees or more)";
            return pc;
          }
        }
      }
      inner = std::isfinite(lam_min) ? lam_min - 2 * min_web : s.length_m;
    } else {
      pc.inside_len[k] = s.length_m;
    }
    if (inner <= 1e-9) continue;
    const Polygon rp = rect_pts(s.axis_origin, u, 0.0, inner, -hw, hw);
    Vec2 where;
    double d = boundary_distance(rp, outline, where);
    if (!fab::point_in_polygon(outline, 0.25 * (rp[0] + rp[1] + rp[2] + rp[3]))) d = 0;
    if (d < min_web - 1e-12) {
      pc.problem = d <= 1e-12 ? slot_words(slots, {k}) + " would break through the edge of " + plate_words + at(where)
                              : slot_words(slots, {k}) + " would leave a web of only " + mm(d, 2) + " mm in " +
                                    plate_words + at(where) + "; the minimum web is " + mmv(min_web) + " mm";
      return pc;
    }
    for (std::size_t j = 0; j < slots.size(); ++j) {
      if (j == k || slots[j].wing == s.wing) continue;
      Vec2 wh;
      const double dj = fab::polygon_distance(rp, slots[j].rect, &wh);
      if (dj < min_web - 1e-12) {
        pc.problem = slot_words(slots, {k, j}) + " would be only " + mm(dj, 2) + " mm apart in " + plate_words +
                     at(wh) + "; the minimum web is " + mmv(min_web) + " mm";
        return pc;
      }
    }
  }
  return pc;
}

// ---------------------------------------------------------------- candidates

Slot make_slot(const std::string& plate, const std::string& wing, Vec2 origin, Vec2 dir, double len, double width,
               bool open) {
  Slot s;
  s.plate = plate;
  s.wing = wing;
  s.open = open;
  s.axis_origin = origin;
  s.axis_dir = dir;
  s.length_m = len;
  s.width_m = width;
  s.rect = rect_pts(origin, dir, 0.0, len, -width / 2, width / 2);
  return s;
}

/// Holes in the fuselage on the wing's slab shadow (through slot, halves).
std::vector<Slot> shadow_holes(const Ctx& c, std::size_t j, const std::vector<Iv>& S) {
  const WingFrame& f = c.frames[j];
  const double cl = c.o.clearance_m;
  std::vector<Slot> out;
  for (const auto& iv : S)
    out.push_back(make_slot("fuselage", c.g.wings[j].name, f.P + (iv.a - cl / 2) * f.d, f.d, iv.b - iv.a + cl, c.w,
                            false));
  return out;
}

std::string wing_words(const Ctx& c, std::size_t j) { return "wing " + quote(c.g.wings[j].name); }

/// Checks the fuselage with closed holes; when a hole breaks through the
/// fuselage's edge at one end (the root chord reaches the edge), tries it as a
/// notch open at that end. Returns the problem ("" when fine); `open` tells
/// whether the notch variant was used.
std::string check_holes(const Ctx& c, std::vector<Slot>& holes, bool& open, std::string& note) {
  open = false;
  const auto closed = check_plate("the fuselage", "x, y", c.fus, c.fus_set, holes, c.o.min_web_m);
  if (closed.problem.empty()) return "";
  if (closed.problem.find("break through the edge") == std::string::npos &&
      closed.problem.find("would leave a web of only") == std::string::npos)
    return closed.problem;  // cut in two, or too close to another wing's slot
  std::vector<Slot> notches = holes;
  bool any = false;
  for (auto& h : notches) {
    const Vec2 a = h.axis_origin, b = h.axis_origin + h.length_m * h.axis_dir;
    const bool ina = fab::point_in_polygon(c.fus, a), inb = fab::point_in_polygon(c.fus, b);
    if (ina == inb) continue;
    h.open = true;
    any = true;
    if (!ina) {  // open at the start: run the axis from the other end
      h.axis_origin = b;
      h.axis_dir = Vec2{-h.axis_dir.x, -h.axis_dir.y};
    }
  }
  std::string notch_problem;
  if (any) {
    const auto pn = check_plate("the fuselage", "x, y", c.fus, c.fus_set, notches, c.o.min_web_m);
    if (pn.problem.empty()) {
      holes = notches;
      open = true;
      note = slot_words(holes, {0}) + " opens at the fuselage's edge, where its root chord reaches the edge";
      return "";
    }
    notch_problem = pn.problem;
  }
  // A channel: where the web between a hole's long side and the plate's edge
  // is thinner than the minimum, that web is cut away (the hole opens to the
  // edge there; a saddle for a wing on the fuselage's top or bottom edge).
  // Elsewhere the hole stays closed. The wing rests on the hole's far face,
  // tilted by the mounting angle, between the closed parts.
  const double mw = c.o.min_web_m;
  std::string channel_problem;
  for (int sg : {+1, -1}) {
    std::vector<Slot> ch;
    bool opened = false;
    double opened_len = 0;
    std::string far_problem;
    for (const auto& h : holes) {
      const Vec2 n{-h.axis_dir.y, h.axis_dir.x};
      const Vec2 up = static_cast<double>(sg) * n, down{-up.x, -up.y};
      const double L = h.length_m, w = h.width_m;
      const int N = std::max(40, static_cast<int>(std::ceil(L / 0.00025)));
      std::vector<double> web(N + 1);
      std::vector<Iv> thin;
      for (int i = 0; i <= N; ++i) {
        const Vec2 q = h.axis_origin + (L * i / N) * h.axis_dir + (w / 2) * up;
        double lam;
        Vec2 e;
        web[i] = first_crossing(c.fus, q, up, c.R, lam, e) ? lam : std::numeric_limits<double>::infinity();
        if (!fab::point_in_polygon(c.fus, q)) web[i] = 0;
        if (web[i] < mw) thin.push_back({std::max(0.0, L * i / N - mw), std::min(L, L * i / N + mw)});
      }
      thin = merge_iv(thin);
      if (thin.empty()) {
        ch.push_back(h);
        continue;
      }
      opened = true;
      // closed parts reach 10 um into the opened parts so that the cut is one
      // region (an exactly shared edge would leave a zero-width wall)
      for (auto piece : iv_subtract({{0.0, L}}, thin)) {
        if (piece.b - piece.a <= 1e-6) continue;
        if (piece.a > 0) piece.a -= 1e-5;
        if (piece.b < L) piece.b += 1e-5;
        ch.push_back(make_slot(h.plate, h.wing, h.axis_origin + piece.a * h.axis_dir, h.axis_dir, piece.b - piece.a, w,
                               false));
      }
      for (const auto& iv : thin) {
        opened_len += iv.b - iv.a;
        // deep enough to break through everywhere along the piece
        double M = 0;
        for (int i = 0; i <= N; ++i) {
          const double si = L * i / N;
          if (si >= iv.a - 1e-12 && si <= iv.b + 1e-12 && std::isfinite(web[i])) M = std::max(M, web[i]);
        }
        M = std::min(M + 0.0002, 3 * mw + c.t);
        const Vec2 origin = h.axis_origin + (0.5 * (iv.a + iv.b)) * h.axis_dir + (w / 2) * down;
        ch.push_back(make_slot(h.plate, h.wing, origin, up, w + M, iv.b - iv.a, true));
        // the web on the far side of the opened part must stay (rays away from the opening)
        for (int i = 0; i <= N && far_problem.empty(); ++i) {
          const double si = L * i / N;
          if (si < iv.a || si > iv.b) continue;
          const Vec2 q = h.axis_origin + si * h.axis_dir + (w / 2) * down;
          if (!fab::point_in_polygon(c.fus, q)) continue;  // no fuselage here at all
          double lam;
          Vec2 e;
          if (first_crossing(c.fus, q, down, c.R, lam, e) && lam < mw - 1e-12)
            far_problem = slot_words(holes, {0}) + " would leave a web of only " + mm(lam, 2) +
                          " mm in the fuselage on both sides near (x, y) = (" + mm(q.x) + ", " + mm(q.y) +
                          ") mm; the minimum web is " + mmv(mw) + " mm";
        }
      }
    }
    if (!opened) continue;
    if (!far_problem.empty()) {
      if (channel_problem.empty()) channel_problem = far_problem;
      continue;
    }
    const auto pc = check_plate("the fuselage", "x, y", c.fus, c.fus_set, ch, c.o.min_web_m);
    if (pc.problem.empty()) {
      holes = ch;
      open = true;
      note = slot_words(holes, {0}) + " is opened to the fuselage's edge over " + mm(opened_len) +
             " mm, where a closed slot would leave less than the " + mmv(mw) +
             " mm minimum web; the wing rests on the slot's far face there (glue it)";
      return "";
    }
    if (channel_problem.empty()) channel_problem = pc.problem;
  }
  if (channel_problem.empty()) channel_problem = "no thin web to open";
  std::string why = closed.problem;
  if (!notch_problem.empty()) why += " (as a notch open at the edge: " + notch_problem + ")";
  why += " (as a channel open to the nearer edge: " + channel_problem + ")";
  return why;
}

Candidate through_slot(const Ctx& c, std::size_t j, const std::vector<Iv>& S, const std::vector<Iv>& BF) {
  Candidate k;
  k.type = JointType::ThroughSlot;
  k.fus_slots = shadow_holes(c, j, S);
  k.ea = S.front().a;
  k.eb = S.back().b;
  k.wing_parts = {c.wing_sets[j]};
  const double t = c.t, R = c.R;
  // Sections that pass through the fuselage when the wing slides in along -z
  // (from the +z side) are the wing with z <= t/2; from the -z side, z >= -t/2.
  std::vector<Iv> holes;
  for (const auto& s : k.fus_slots) {
    const double a = dot(s.axis_origin - c.frames[j].P, c.frames[j].d);
    holes.push_back({a, a + s.length_m});
  }
  double best_aft = 0, best_fwd = 0, best = std::numeric_limits<double>::infinity();
  for (int dir : {+1, -1}) {
    const Polygon pass = dir > 0 ? rect_pts({0, 0}, {1, 0}, -R, R, -R, t / 2) : rect_pts({0, 0}, {1, 0}, -R, R, -t / 2, R);
    const auto P = project(c.wing_sets[j], pass, {0, 0}, {1, 0});
    const auto hit = iv_intersect(iv_subtract(P, holes), BF);
    double aft = 0, fwd = 0;
    for (const auto& h : hit) {
      if (h.b - h.a < 1e-7) continue;
      aft = std::max(aft, holes.front().a - h.a);
      fwd = std::max(fwd, h.b - holes.back().b);
    }
    if (aft <= 0 && fwd <= 0) {
      k.dir = dir;
      break;
    }
    if (std::max(aft, fwd) < best) {
      best = std::max(aft, fwd);
      best_aft = aft;
      best_fwd = fwd;
    }
  }
  if (k.dir == 0) {
    std::string where;
    if (best_aft > 0) where = mm(best_aft) + " mm behind";
    if (best_fwd > 0) where += (where.empty() ? "" : " and ") + mm(best_fwd) + " mm ahead of";
    k.problem = wing_words(c, j) + " cannot slide sideways through a closed slot: its outer sections reach " + where +
                " its root chord (a swept, crescent or widening planform), so they would hit the fuselage";
    return k;
  }
  bool open = false;
  k.problem = check_holes(c, k.fus_slots, open, k.note);
  if (open) k.type = JointType::Notch;
  return k;
}

Candidate halves(const Ctx& c, std::size_t j, const std::vector<Iv>& S) {
  Candidate k;
  k.type = JointType::Halves;
  k.dir = +1;
  k.fus_slots = shadow_holes(c, j, S);
  k.ea = S.front().a;
  k.eb = S.back().b;
  k.split = 0.5 * (k.ea + k.eb);
  const double t = c.t, R = c.R, x = k.split;
  // right: {z >= t/2} ∪ {z >= -t/2, x >= split}; left: the mirror with x <= split
  const Polygon right{{-R, t / 2}, {x, t / 2}, {x, -t / 2}, {R, -t / 2}, {R, R}, {-R, R}};
  const Polygon left{{R, -t / 2}, {x, -t / 2}, {x, t / 2}, {-R, t / 2}, {-R, -R}, {R, -R}};
  for (const auto& reg : {right, left}) {
    EPset h(c.wing_sets[j]);
    h.intersection(exact(reg));
    if (pieces(h) != 1) {
      k.problem = "splitting " + wing_words(c, j) + " at its root would leave a half in more than one piece";
      return k;
    }
    k.wing_parts.push_back(h);
  }
  bool open = false;
  k.problem = check_holes(c, k.fus_slots, open, k.note);
  return k;
}

Candidate cross_lap(const Ctx& c, std::size_t j, int dir, const std::vector<Iv>& S, const std::vector<Iv>& BF) {
  Candidate k;
  k.type = JointType::CrossLap;
  k.dir = dir;
  const auto O = iv_intersect(S, BF);
  const std::string side = dir > 0 ? "a cross-lap slot opening behind the wing" : "a cross-lap slot opening ahead of the wing";
  if (O.empty()) {
    k.problem = wing_words(c, j) + "'s root does not overlap the fuselage";
    return k;
  }
  const double sa = O.front().a, sb = O.back().b;
  const double need = 2 * std::max(c.o.min_web_m, c.t);
  if (sb - sa < need) {
    k.problem = wing_words(c, j) + "'s root overlaps the fuselage over only " + mm(sb - sa) +
                " mm, too short for a cross-lap (needs " + mm(need) + " mm)";
    return k;
  }
  k.ea = sa;
  k.eb = sb;
  k.split = 0.5 * (sa + sb);
  const WingFrame& f = c.frames[j];
  const double R = c.R, x = k.split;
  const std::string wn = c.g.wings[j].name;
  // dir +1: the wing slides forward (+d) from behind: fuselage slot toward -d,
  // wing slot from the leading edge back to the split.
  const Vec2 back{-f.d.x, -f.d.y};
  k.fus_slots = {dir > 0 ? make_slot("fuselage", wn, f.P + x * f.d, back, R + x, c.w, true)
                         : make_slot("fuselage", wn, f.P + x * f.d, f.d, R - x, c.w, true)};
  k.wing_slots = {dir > 0 ? make_slot(wn, wn, {x, 0}, {1, 0}, R - x, c.w, true)
                          : make_slot(wn, wn, {x, 0}, {-1, 0}, R + x, c.w, true)};
  const auto pf = check_plate("the fuselage", "x, y", c.fus, c.fus_set, k.fus_slots, c.o.min_web_m);
  if (!pf.problem.empty()) {
    k.problem = side + ": " + pf.problem;
    return k;
  }
  k.fus_len = pf.inside_len.empty() ? 0 : pf.inside_len[0];
  const auto pw = check_plate(wing_words(c, j), "x, z", c.wings[j], c.wing_sets[j], k.wing_slots, c.o.min_web_m);
  if (!pw.problem.empty()) {
    k.problem = side + ": " + pw.problem;
    return k;
  }
  k.wing_parts = {pw.result};
  return k;
}

struct WingOptions {
  std::vector<Candidate> feasible;
  std::vector<std::pair<JointType, std::string>> refused;
};

WingOptions wing_options(const Ctx& c, std::size_t j, JointType want) {
  WingOptions out;
  const WingFrame& f = c.frames[j];
  const double t = c.t, R = c.R, h = std::min(c.w, c.t) / 2;
  const auto S = project(c.wing_sets[j], rect_pts({0, 0}, {1, 0}, -R, R, -t / 2, t / 2), {0, 0}, {1, 0});
  const auto BF = project(c.fus_set, rect_pts(f.P, f.d, -R, R, -h, h), f.P, f.d);
  if (S.empty()) {
    out.refused.push_back({JointType::Auto, wing_words(c, j) + " has no material at its root (z = 0)"});
    return out;
  }
  auto consider = [&](Candidate k) {
    if (k.problem.empty()) out.feasible.push_back(std::move(k));
    else out.refused.push_back({k.type, k.problem});
  };
  if (want == JointType::Auto || want == JointType::ThroughSlot || want == JointType::Notch) {
    Candidate k = through_slot(c, j, S, BF);
    if (k.problem.empty() && want != JointType::Auto && k.type != want)
      k.problem = want == JointType::ThroughSlot
                      ? wing_words(c, j) + "'s root chord reaches the fuselage's edge, so its slot is an open notch"
                      : wing_words(c, j) + "'s root chord lies inside the fuselage, so its slot is closed (a through slot)";
    consider(std::move(k));
  }
  // Cross-laps: a short open slot (no longer than the joint itself) is
  // preferred to splitting the wing; a long one weakens the fuselage and is
  // used only when nothing else works (docs/fabrication.md, "Choice").
  std::vector<Candidate> laps_short, laps_long;
  if (want == JointType::Auto || want == JointType::CrossLap) {
    Candidate a = cross_lap(c, j, +1, S, BF), b = cross_lap(c, j, -1, S, BF);
    if (!a.problem.empty() && !b.problem.empty())
      out.refused.push_back({JointType::CrossLap, a.problem + "; " + b.problem});
    std::vector<Candidate> ok;
    for (auto* k : {&a, &b})
      if (k->problem.empty()) ok.push_back(std::move(*k));
    // the shorter fuselage slot weakens the fuselage less
    std::sort(ok.begin(), ok.end(), [](const Candidate& x, const Candidate& y) { return x.fus_len < y.fus_len; });
    for (auto& k : ok) {
      const double joint_len = k.eb - k.ea;
      k.long_lap = k.fus_len - joint_len / 2 > joint_len;
      (want == JointType::CrossLap || !k.long_lap ? laps_short : laps_long).push_back(std::move(k));
    }
  }
  for (auto& k : laps_short) out.feasible.push_back(std::move(k));
  if (want == JointType::Auto || want == JointType::Halves) consider(halves(c, j, S));
  if (!laps_long.empty() && want == JointType::Auto && !out.feasible.empty())
    out.refused.push_back({JointType::CrossLap, "a cross-lap would need an open slot " + mm(laps_long.front().fus_len) +
                                                    " mm long in the fuselage, weakening it; splitting the wing is preferred"});
  for (auto& k : laps_long) out.feasible.push_back(std::move(k));
  return out;
}

// ------------------------------------------------------------- side view

/// The wing's side-view footprint: chord interval [x0, x1] of the wing frame,
/// thickness t, in the glider x-y plane.
Polygon side_rect(const Ctx& c, std::size_t j, double x0, double x1) {
  const WingFrame& f = c.frames[j];
  return rect_pts(f.P, f.d, x0, x1, -c.t / 2, c.t / 2);
}

bool overlaps(const Polygon& a, const Polygon& b) {
  EPset s(exact(a));
  s.intersection(exact(b));
  std::vector<EPwh> pw;
  s.polygons_with_holes(std::back_inserter(pw));
  double area = 0;
  for (const auto& p : pw) area += std::fabs(CGAL::to_double(p.outer_boundary().area()));
  return area > 1e-12;  // 1 mm^2
}

std::pair<double, double> x_range(const Polygon& p) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& v : p) {
    lo = std::min(lo, v.x);
    hi = std::max(hi, v.x);
  }
  return {lo, hi};
}

/// Assembly order of the wings for a choice of joints, or "" + order.
/// Returns a problem sentence when two wings lie on each other's way in.
std::string assembly_order(const Ctx& c, const std::vector<const Candidate*>& pick, std::vector<std::size_t>& order) {
  const std::size_t n = pick.size();
  std::vector<std::vector<bool>> before(n, std::vector<bool>(n, false));  // before[a][b]: a goes in before b
  for (std::size_t a = 0; a < n; ++a) {
    if (pick[a]->type != JointType::CrossLap) continue;
    const auto [lo, hi] = x_range(c.wings[a]);
    const Polygon path = pick[a]->dir > 0 ? side_rect(c, a, -c.R, hi) : side_rect(c, a, lo, c.R);
    for (std::size_t b = 0; b < n; ++b) {
      if (b == a) continue;
      const auto [blo, bhi] = x_range(c.wings[b]);
      if (overlaps(path, side_rect(c, b, blo, bhi))) before[a][b] = true;
    }
  }
  order.clear();
  std::vector<bool> done(n, false);
  for (std::size_t step = 0; step < n; ++step) {
    std::size_t next = n;
    for (std::size_t b = 0; b < n && next == n; ++b) {
      if (done[b]) continue;
      bool free = true;
      for (std::size_t a = 0; a < n; ++a)
        if (!done[a] && a != b && before[a][b]) free = false;
      if (free) next = b;
    }
    if (next == n) {
      for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = 0; b < n; ++b)
          if (!done[a] && !done[b] && before[a][b] && before[b][a])
            return "wings " + quote(c.g.wings[a].name) + " and " + quote(c.g.wings[b].name) +
                   " each lie on the other's way in along its chord";
      return "the wings' ways in along their chords block each other";
    }
    done[next] = true;
    order.push_back(next);
  }
  return "";
}

// ------------------------------------------------------------------- marks

struct MarkCtx {
  fab::Region reg;
  std::vector<Polygon> used;  // text boxes already placed
};

double text_half_width(const std::string& s, double h) { return 0.5 * (0.75 * h * static_cast<double>(s.size()) + 0.2 * h); }

bool place_text(MarkCtx& m, Plate& p, const std::string& text, Vec2 pref, double h_max, double pref_angle_deg,
                std::vector<std::string>& warnings) {
  const auto [lo, hi] = bounds(m.reg.outline);
  const double diag = norm(hi - lo);
  const double margin = 0.0005;
  for (double h = h_max; h >= 0.0012; h *= 0.8) {
    for (double ang : {pref_angle_deg, pref_angle_deg + 90.0}) {
      const double a = deg2rad(ang);
      const double hx = text_half_width(text, h), hy = 0.6 * h;
      const double step = std::max(h / 2, diag / 120);
      std::vector<Vec2> cand;
      for (double x = lo.x + hx * 0.0; x <= hi.x; x += step)
        for (double y = lo.y; y <= hi.y; y += step) cand.push_back({x, y});
      std::sort(cand.begin(), cand.end(), [&](Vec2 u, Vec2 v) { return norm(u - pref) < norm(v - pref); });
      for (const auto& q : cand) {
        const Polygon box = fab::oriented_box(q, hx, hy, a);
        if (!fab::box_fits(m.reg, box, margin)) continue;
        bool clash = false;
        for (const auto& u : m.used)
          if (fab::polygon_distance(box, u) < margin) clash = true;
        if (clash) continue;
        m.used.push_back(box);
        Mark mk;
        mk.kind = Mark::Kind::Text;
        mk.points = {q};
        mk.text = text;
        mk.size_m = h;
        mk.angle_deg = std::fmod(ang, 360.0);
        p.marks.push_back(mk);
        return true;
      }
    }
  }
  warnings.push_back("no room to engrave '" + text + "' on " + p.name);
  return false;
}

void add_line(MarkCtx& m, Plate& p, Vec2 a, Vec2 b, const std::string& what) {
  for (const auto& [u, v] : fab::clip_segment(m.reg, a, b, 0.0003)) {
    Mark mk;
    mk.kind = Mark::Kind::Line;
    mk.points = {u, v};
    mk.text = what;
    p.marks.push_back(mk);
  }
}

bool add_cross(MarkCtx& m, Plate& p, Vec2 c, double arm, const std::string& what) {
  if (!fab::inside(m.reg, c) || fab::distance_to_boundary(m.reg, c) < 0.0005) return false;
  Mark mk;
  mk.kind = Mark::Kind::Cross;
  mk.points = {c};
  mk.size_m = std::min(arm, 0.9 * fab::distance_to_boundary(m.reg, c));
  mk.text = what;
  p.marks.push_back(mk);
  m.used.push_back(fab::oriented_box(c, mk.size_m, mk.size_m, 0));
  return true;
}

std::string grams(double kg) { return num(kg * 1000.0, kg * 1000 < 10 ? 1 : 0); }

// ------------------------------------------------------------------ plates

Polygon area_ccw(const Polygon& p, bool ccw) {
  Polygon q = fab::clean_polygon(p, 1e-9);
  if ((signed_area(q) > 0) != ccw) std::reverse(q.begin(), q.end());
  return q;
}

void fill_region(Plate& p, const EPset& s) {
  std::vector<EPwh> pw;
  s.polygons_with_holes(std::back_inserter(pw));
  const EPwh& r = pw.front();
  p.outline = area_ccw(to_dbl(r.outer_boundary()), true);
  p.holes.clear();
  for (auto it = r.holes_begin(); it != r.holes_end(); ++it) p.holes.push_back(area_ccw(to_dbl(*it), false));
  p.area_m2 = std::fabs(signed_area(p.outline));
  for (const auto& h : p.holes) p.area_m2 -= std::fabs(signed_area(h));
}

std::array<double, 16> wing_transform(const WingFrame& f) {
  const double c = std::cos(f.theta), s = std::sin(f.theta);
  // columns: u -> d = (c, s, 0), v -> e_z, w -> d x e_z = (s, -c, 0)
  return {c, 0, s, f.P.x,  //
          s, 0, -c, f.P.y,  //
          0, 1, 0, 0,       //
          0, 0, 0, 1};
}

}  // namespace

std::array<double, 3> plate_to_glider(const Plate& p, double u, double v, double w) {
  const auto& M = p.transform;
  return {M[0] * u + M[1] * v + M[2] * w + M[3], M[4] * u + M[5] * v + M[6] * w + M[7],
          M[8] * u + M[9] * v + M[10] * w + M[11]};
}

PlateSet slotted_plates(const Glider& g, const FabricationOptions& o) {
  validate(g);
  const double t = o.thickness_m > 0 ? o.thickness_m : g.material.thickness_m;
  check_fabrication_options(o, t);
  for (const auto& joint : o.joints) {
    const std::string& name = joint.first;  // (clang 14 cannot capture a structured binding)
    if (name == "*") continue;
    if (std::none_of(g.wings.begin(), g.wings.end(), [&](const Wing& w) { return w.name == name; })) {
      std::string names;
      for (const auto& w : g.wings) names += (names.empty() ? "'" : ", '") + w.name + "'";
      throw InputError("a joint is requested for wing '" + name + "' but the glider's wings are " + names);
    }
  }
  const Ctx c(g, o, t);
  const std::size_t nw = g.wings.size();

  // Wings that cross each other where they meet the fuselage cannot be built.
  for (std::size_t a = 0; a < nw; ++a)
    for (std::size_t b = a + 1; b < nw; ++b) {
      const auto ra = root_chord_intervals(g.wings[a].outline), rb = root_chord_intervals(g.wings[b].outline);
      if (ra.empty() || rb.empty()) continue;
      if (overlaps(side_rect(c, a, ra.front().first, ra.back().second),
                   side_rect(c, b, rb.front().first, rb.back().second)))
        throw InputError("wings '" + g.wings[a].name + "' and '" + g.wings[b].name +
                         "' pass through each other at their roots (their root chords cross in the side view); "
                         "move one of them");
    }

  // Joint options per wing.
  std::vector<WingOptions> opts;
  for (std::size_t j = 0; j < nw; ++j) {
    JointType want = JointType::Auto;
    if (auto it = o.joints.find(g.wings[j].name); it != o.joints.end()) want = it->second;
    else if (auto st = o.joints.find("*"); st != o.joints.end()) want = st->second;
    opts.push_back(wing_options(c, j, want));
    if (opts.back().feasible.empty()) {
      std::string why;
      for (const auto& [type, reason] : opts.back().refused)
        why += (why.empty() ? "" : "; ") + (type == JointType::Auto ? "" : joint_type_name(type) + ": ") + reason;
      throw InputError("no joint can hold wing '" + g.wings[j].name + "': " + why);
    }
  }

  // First combination (in order of preference) whose slots fit together in
  // the fuselage and whose wings can go in one after the other.
  std::vector<std::size_t> idx(nw, 0), order;
  std::vector<const Candidate*> pick(nw);
  PlateCheck fus_check;
  std::string first_problem;
  bool found = false;
  auto advance = [&]() -> bool {  // next combination, last wing varies fastest
    for (std::size_t k = nw; k-- > 0;) {
      if (++idx[k] < opts[k].feasible.size()) return true;
      idx[k] = 0;
    }
    return false;
  };
  do {
    std::vector<Slot> slots;
    for (std::size_t j = 0; j < nw; ++j) {
      pick[j] = &opts[j].feasible[idx[j]];
      slots.insert(slots.end(), pick[j]->fus_slots.begin(), pick[j]->fus_slots.end());
    }
    fus_check = check_plate("the fuselage", "x, y", c.fus, c.fus_set, slots, o.min_web_m);
    std::string problem = fus_check.problem;
    if (problem.empty()) problem = assembly_order(c, pick, order);
    if (problem.empty()) found = true;
    else if (first_problem.empty()) first_problem = problem;
  } while (!found && advance());
  if (!found) throw InputError("the wings' joints do not fit together: " + first_problem);

  // ---------------------------------------------------------------- plates
  PlateSet out;
  out.glider = g.name;
  out.thickness_m = t;
  out.options = o;
  const MassProperties mp = mass_properties(g);
  const std::string prefix = g.name.empty() ? "" : g.name + " ";
  const double th = o.text_height_m;

  for (std::size_t j = 0; j < nw; ++j) {
    const Candidate& k = *pick[j];
    Joint jt;
    jt.wing = g.wings[j].name;
    jt.type = k.type;
    jt.direction = k.dir;
    jt.split_x_m = k.split;
    jt.engaged_from_m = k.ea;
    jt.engaged_to_m = k.eb;
    jt.slots = k.fus_slots;
    jt.slots.insert(jt.slots.end(), k.wing_slots.begin(), k.wing_slots.end());
    jt.refused = opts[j].refused;
    for (std::size_t q = 0; q < idx[j]; ++q)
      if (opts[j].feasible[q].type != k.type)
        jt.refused.push_back({opts[j].feasible[q].type,
                              "it fits alone but not together with the other wings' joints"});
    // Keep the reasons a person would ask for: why not a joint preferred to
    // the chosen one (never the chosen type itself).
    jt.refused.erase(std::remove_if(jt.refused.begin(), jt.refused.end(),
                                    [&](const auto& r) {
                                      return r.first == k.type || k.type == JointType::ThroughSlot ||
                                             k.type == JointType::Notch ||
                                             (k.type == JointType::CrossLap && !k.long_lap &&
                                              r.first == JointType::Halves);
                                    }),
                     jt.refused.end());
    out.joints.push_back(jt);
    if (!k.note.empty()) out.warnings.push_back(k.note);
  }
  for (std::size_t s = 0; s < order.size(); ++s) out.joints[order[s]].step = static_cast<int>(s) + 1;

  // Fuselage.
  {
    Plate p;
    p.name = "fuselage";
    p.kind = "fuselage";
    p.label = prefix + "fuselage";
    p.thickness_m = t;
    p.transform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    p.design_area_m2 = std::fabs(signed_area(g.fuselage));
    fill_region(p, fus_check.result);
    for (std::size_t j = 0; j < nw; ++j) p.joints.push_back(j);
    MarkCtx m{{p.outline, p.holes}, {}};
    // wing positions: ticks across the slot at the root chord's ends, and the name
    for (std::size_t j = 0; j < nw; ++j) {
      const WingFrame& f = c.frames[j];
      const Vec2 n{-f.d.y, f.d.x};
      const auto roots = root_chord_intervals(g.wings[j].outline);
      const double xt = roots.front().first, xl = roots.back().second;
      for (double s : {xt, xl})
        for (double sg : {-1.0, 1.0})
          add_line(m, p, f.P + s * f.d + (sg * (c.w / 2 + 0.0006)) * n, f.P + s * f.d + (sg * (c.w / 2 + 0.003)) * n,
                   "wing " + g.wings[j].name + (s == xl ? " leading edge" : " trailing edge"));
    }
    place_text(m, p, p.label, [&] {
      const AreaMoments am = area_moments(p.outline);
      return Vec2{am.Sx / am.A, am.Sy / am.A};
    }(), th, 0.0, out.warnings);
    if (add_cross(m, p, mp.cg, 0.003, "centre of gravity"))
      place_text(m, p, "CG", mp.cg + Vec2{0, 0.004}, 0.75 * th, 0.0, out.warnings);
    else {
      add_line(m, p, {mp.cg.x, -c.R}, {mp.cg.x, c.R}, "centre of gravity (x)");
      place_text(m, p, "CG", mp.cg, 0.75 * th, 90.0, out.warnings);
    }
    for (const auto& b : g.ballast) {
      const std::string txt = b.name + " " + grams(b.mass_kg) + " g";
      if (add_cross(m, p, {b.x_m, b.y_m}, 0.0025, "ballast " + b.name))
        place_text(m, p, txt, Vec2{b.x_m, b.y_m} + Vec2{0, 0.004}, 0.75 * th, 0.0, out.warnings);
      else
        out.warnings.push_back("ballast '" + b.name + "' at (" + mm(b.x_m) + ", " + mm(b.y_m) +
                               ") mm is not on the fuselage plate's material; its mark is left out");
    }
    for (std::size_t j = 0; j < nw; ++j) {
      const WingFrame& f = c.frames[j];
      const Vec2 n{-f.d.y, f.d.x};
      const double mid = 0.5 * (pick[j]->ea + pick[j]->eb);
      place_text(m, p, g.wings[j].name, f.P + mid * f.d + (c.w / 2 + 0.004) * n, 0.75 * th,
                 rad2deg(f.theta), out.warnings);
    }
    out.plates.push_back(std::move(p));
  }

  // Wings.
  for (std::size_t j = 0; j < nw; ++j) {
    const Candidate& k = *pick[j];
    const WingFrame& f = c.frames[j];
    const std::string wn = g.wings[j].name;
    for (std::size_t part = 0; part < k.wing_parts.size(); ++part) {
      Plate p;
      p.kind = "wing";
      p.wing = wn;
      p.half = k.wing_parts.size() == 2 ? (part == 0 ? "right" : "left") : "";
      p.name = p.half.empty() ? wn : wn + " (" + p.half + " half)";
      p.label = prefix + p.name;
      p.thickness_m = t;
      p.transform = wing_transform(f);
      p.design_area_m2 = std::fabs(signed_area(g.wings[j].outline));
      p.joints = {j};
      fill_region(p, k.wing_parts[part]);
      MarkCtx m{{p.outline, p.holes}, {}};
      const AreaMoments am = area_moments(p.outline);
      place_text(m, p, p.label, {am.Sx / am.A, am.Sy / am.A}, th, 90.0, out.warnings);
      if (k.type == JointType::ThroughSlot || k.type == JointType::Notch)
        for (double sg : {-1.0, 1.0})
          add_line(m, p, {k.ea, sg * t / 2}, {k.eb, sg * t / 2}, "fuselage face");
      // balance marks: the centre of gravity's chord position
      const double xcg = dot(mp.cg - f.P, f.d);
      bool any = false;
      for (double sg : {-1.0, 1.0}) {
        const std::size_t before = p.marks.size();
        add_line(m, p, {xcg, sg * (t / 2 + 0.004)}, {xcg, sg * (t / 2 + 0.014)}, "centre of gravity");
        any = any || p.marks.size() > before;
      }
      if (any) {
        const double zs = p.half == "left" ? -1.0 : 1.0;
        place_text(m, p, "CG", {xcg, zs * (t / 2 + 0.02)}, 0.75 * th, 90.0, out.warnings);
      }
      out.plates.push_back(std::move(p));
    }
  }
  for (std::size_t i = 0; i < out.plates.size(); ++i) {
    Plate& p = out.plates[i];
    if (p.kind == "wing") {
      for (std::size_t j = 0; j < nw; ++j)
        if (g.wings[j].name == p.wing) p.joints = {j};
    }
    auto [co, ch] = offset_for_kerf(p.outline, p.holes, o.kerf_m / 2);
    p.cut_outline = std::move(co);
    p.cut_holes = std::move(ch);
  }

  // Assembly steps.
  out.assembly.push_back("Cut every part. The fuselage's engraved face is the glider's right side (+z).");
  for (std::size_t s = 0; s < order.size(); ++s) {
    const std::size_t j = order[s];
    const Joint& jt = out.joints[j];
    const std::string wn = "'" + jt.wing + "'";
    std::string how;
    switch (jt.type) {
      case JointType::ThroughSlot:
        how = "Slide wing " + wn + " sideways through its tilted slot in the fuselage, from the " +
              std::string(jt.direction > 0 ? "engraved" : "plain") + " side (" +
              (jt.direction > 0 ? "left" : "right") +
              " tip first), until the two engraved lines on its root meet the fuselage's faces.";
        break;
      case JointType::Notch:
        how = "Slide wing " + wn + " sideways into its tilted notch at the fuselage's edge, from the " +
              std::string(jt.direction > 0 ? "engraved" : "plain") +
              " side, until the two engraved lines on its root meet the fuselage's faces and its root rests "
              "against the closed end of the notch.";
        break;
      case JointType::CrossLap:
        how = "Slide wing " + wn + (jt.direction > 0 ? " forward" : " backward") + " along its chord, its " +
              (jt.direction > 0 ? "leading-edge" : "trailing-edge") + " slot over the fuselage's slot that opens " +
              (jt.direction > 0 ? "toward the tail" : "toward the nose") + ", until both slots bottom out.";
        break;
      case JointType::Halves:
        how = "Push '" + jt.wing + " (right half)' into its slot from the engraved side of the fuselage until its "
              "shoulder meets the fuselage, then '" + jt.wing + " (left half)' from the other side; their root tabs "
              "fill the slot.";
        break;
      default: break;
    }
    out.joints[j].how = how;
    out.assembly.push_back(how);
  }
  out.assembly.push_back("Glue the joints, then fix the ballast at its engraved mark and check the balance at the CG marks.");
  return out;
}

// ------------------------------------------------------------------ summary

nlohmann::json plates_summary(const PlateSet& s) {
  using nlohmann::json;
  json j;
  j["glider"] = s.glider;
  j["thickness_mm"] = s.thickness_m * 1000;
  j["kerf_mm"] = s.options.kerf_m * 1000;
  j["clearance_mm"] = s.options.clearance_m * 1000;
  j["slot_width_mm"] = (s.thickness_m + s.options.clearance_m) * 1000;
  j["min_web_mm"] = s.options.min_web_m * 1000;
  json parts = json::array();
  for (const auto& p : s.plates) {
    json q;
    q["name"] = p.name;
    q["kind"] = p.kind;
    if (!p.wing.empty()) q["wing"] = p.wing;
    if (!p.half.empty()) q["half"] = p.half;
    q["label"] = p.label;
    q["area_mm2"] = p.area_m2 * 1e6;
    q["holes"] = p.holes.size();
    const auto [lo, hi] = bounds(p.outline);
    q["size_mm"] = {(hi.x - lo.x) * 1000, (hi.y - lo.y) * 1000};
    parts.push_back(q);
  }
  j["parts"] = parts;
  json joints = json::array();
  for (const auto& jt : s.joints) {
    json q;
    q["wing"] = jt.wing;
    q["type"] = joint_type_name(jt.type);
    q["direction"] = jt.direction;
    q["split_x_mm"] = jt.split_x_m * 1000;
    q["engaged_mm"] = {jt.engaged_from_m * 1000, jt.engaged_to_m * 1000};
    q["step"] = jt.step;
    q["how"] = jt.how;
    json r = json::array();
    for (const auto& [type, reason] : jt.refused) r.push_back({{"type", joint_type_name(type)}, {"reason", reason}});
    q["refused"] = r;
    joints.push_back(q);
  }
  j["joints"] = joints;
  j["assembly"] = s.assembly;
  j["warnings"] = s.warnings;
  return j;
}

}  // namespace pteromys
