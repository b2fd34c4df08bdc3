#include "pteromys/elements.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pteromys/geometry.hpp"

namespace pteromys {
namespace {

// x(z) along a polygon edge.
struct EdgeLine {
  double x0, z0, slope;  // x = x0 + slope * (z - z0)
  double at(double z) const { return x0 + slope * (z - z0); }
};

// A slab (za, zb) between consecutive breakpoints: no vertex inside, so the
// planform inside it is a set of exact trapezoids bounded by edge lines.
struct Slab {
  double za, zb;
  std::vector<std::pair<EdgeLine, EdgeLine>> pieces;  // (trailing, leading), leading = larger x; sorted by leading x descending
};

}  // namespace

WingElements slice_wing(const Polygon& outline_in, double dz) {
  if (!(dz > 0) || !std::isfinite(dz)) throw InputError("element spacing dz must be positive");
  if (outline_in.size() < 3) throw InputError("wing outline needs at least 3 points");
  const Polygon& p = outline_in;  // (x, z) stored as (x, y)
  const std::size_t n = p.size();

  WingElements out;
  out.planform_area = std::abs(signed_area(p));
  const auto [lo, hi] = bounds(p);
  out.span = hi.y - lo.y;

  // Breakpoints: every vertex z and every cut line k * dz inside the span.
  std::vector<double> zs;
  for (const auto& v : p) zs.push_back(v.y);
  const long kmin = static_cast<long>(std::ceil(lo.y / dz));
  const long kmax = static_cast<long>(std::floor(hi.y / dz));
  if (kmax - kmin > 200000) throw InputError("element spacing dz is too small for this wing");
  for (long k = kmin; k <= kmax; ++k) zs.push_back(k * dz);
  std::sort(zs.begin(), zs.end());
  zs.erase(std::unique(zs.begin(), zs.end()), zs.end());

  const double eps_z = 1e-12 * std::max(1.0, out.span);
  std::vector<Slab> slabs;
  for (std::size_t s = 0; s + 1 < zs.size(); ++s) {
    const double za = zs[s], zb = zs[s + 1];
    if (zb - za <= eps_z) continue;
    const double zm = 0.5 * (za + zb);
    std::vector<std::pair<double, EdgeLine>> cross;  // (x at zm, line)
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = p[i], b = p[(i + 1) % n];
      if ((a.y < zm && b.y > zm) || (b.y < zm && a.y > zm)) {
        EdgeLine e{a.x, a.y, (b.x - a.x) / (b.y - a.y)};
        cross.emplace_back(e.at(zm), e);
      }
    }
    std::sort(cross.begin(), cross.end(), [](const auto& u, const auto& v) { return u.first < v.first; });
    Slab sl{za, zb, {}};
    for (std::size_t i = 0; i + 1 < cross.size(); i += 2)
      sl.pieces.emplace_back(cross[i].second, cross[i + 1].second);
    std::reverse(sl.pieces.begin(), sl.pieces.end());  // most upstream (largest x) first
    if (!sl.pieces.empty()) slabs.push_back(std::move(sl));
  }

  // Group slabs into elements: within one cut interval [k dz, (k+1) dz], runs
  // of consecutive slabs with the same number of pieces; one element per
  // piece index in each run.
  auto cut_index = [&](double zm) { return static_cast<long>(std::floor(zm / dz)); };
  std::size_t s = 0;
  while (s < slabs.size()) {
    const long k = cut_index(0.5 * (slabs[s].za + slabs[s].zb));
    const std::size_t npieces = slabs[s].pieces.size();
    std::size_t e = s + 1;
    while (e < slabs.size() && cut_index(0.5 * (slabs[e].za + slabs[e].zb)) == k &&
           slabs[e].pieces.size() == npieces && std::abs(slabs[e].za - slabs[e - 1].zb) <= eps_z)
      ++e;
    const double z0 = slabs[s].za, z1 = slabs[e - 1].zb;
    const bool positive_side = 0.5 * (z0 + z1) >= 0;
    for (std::size_t j = 0; j < npieces; ++j) {
      double area = 0, int_le = 0;
      for (std::size_t q = s; q < e; ++q) {
        const auto& [te, le] = slabs[q].pieces[j];
        const double zm = 0.5 * (slabs[q].za + slabs[q].zb), w = slabs[q].zb - slabs[q].za;
        area += w * (le.at(zm) - te.at(zm));  // exact: integrand is linear in z
        int_le += w * le.at(zm);
      }
      WingElement el;
      el.z0 = z0;
      el.z1 = z1;
      el.area = area;
      el.chord = area / (z1 - z0);
      el.x_le = int_le / (z1 - z0);
      el.x_qc = el.x_le - 0.25 * el.chord;
      // Edge positions at the inboard and outboard cut lines (one-sided limits).
      const auto& first = slabs[s].pieces[j];
      const auto& last = slabs[e - 1].pieces[j];
      const double le_z0 = first.second.at(z0), te_z0 = first.first.at(z0);
      const double le_z1 = last.second.at(z1), te_z1 = last.first.at(z1);
      const double w = z1 - z0;
      // Outboard = away from z = 0. Sweep positive when the edge moves aft outboard.
      const double dle = positive_side ? (le_z0 - le_z1) : (le_z1 - le_z0);
      const double dte = positive_side ? (te_z0 - te_z1) : (te_z1 - te_z0);
      el.xi_l = std::atan2(dle, w);
      el.xi_t = std::atan2(dte, w);
      el.streamline_rank = static_cast<int>(j);
      out.elements.push_back(el);
    }
    if (npieces > 1) {
      out.multiple_in_streamline = true;
      if (!out.multiple_ranges.empty() && std::abs(out.multiple_ranges.back().second - z0) <= eps_z)
        out.multiple_ranges.back().second = z1;
      else
        out.multiple_ranges.emplace_back(z0, z1);
    }
    s = e;
  }
  return out;
}

}  // namespace pteromys
