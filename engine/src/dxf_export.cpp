// DXF for laser cutting, written with dxflib (docs/fabrication.md, "DXF").
#include "pteromys/io.hpp"
#include "pteromys/dxf_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <unistd.h>

#include <dl_dxf.h>

#include "pteromys/fabrication_geometry.hpp"
#include "pteromys/geometry.hpp"

namespace pteromys {
namespace {

std::string mmv(double m) {
  char b[64];
  std::snprintf(b, sizeof b, "%g", m * 1000.0);
  return b;
}

constexpr double kSheetSpacing = 0.05;  // between sheets in the DXF [m]

Vec2 place(const Placement& pl, Vec2 p) {
  const Vec2 r = pl.rotation_deg == 0 ? p : Vec2{-p.y, p.x};
  return r + pl.offset;
}

}  // namespace

double sheet_x_offset(const SheetOptions& o, int k) { return k * (o.width_m + kSheetSpacing); }

Layout layout_plates(const PlateSet& s, const SheetOptions& o) {
  auto ok = [](double v) { return std::isfinite(v) && v >= 0; };
  if (!ok(o.width_m) || !ok(o.height_m) || o.width_m <= 0 || o.height_m <= 0)
    throw InputError("sheet size must be two positive numbers of mm (got " + mmv(o.width_m) + " x " + mmv(o.height_m) + ")");
  if (o.width_m > 10 || o.height_m > 10) throw InputError("sheet size is larger than 10 m; the size is in mm (600x900)");
  if (!ok(o.margin_m) || !ok(o.gap_m)) throw InputError("sheet margin and gap between parts must be numbers >= 0 mm");
  const double W = o.width_m - 2 * o.margin_m, H = o.height_m - 2 * o.margin_m;
  if (W <= 0 || H <= 0) throw InputError("the sheet margins leave no room on a " + mmv(o.width_m) + " x " + mmv(o.height_m) + " mm sheet");

  struct Item {
    std::size_t i;
    double w, h;  // placed size
    bool rot;
    Vec2 lo, hi;  // unrotated bounds
  };
  std::vector<Item> items;
  for (std::size_t i = 0; i < s.plates.size(); ++i) {
    const auto [lo, hi] = bounds(s.plates[i].cut_outline);
    const double wx = hi.x - lo.x, wy = hi.y - lo.y;
    const bool fit0 = wx <= W && wy <= H, fit90 = wy <= W && wx <= H;
    if (!fit0 && !fit90)
      throw InputError("part '" + s.plates[i].name + "' (" + mmv(std::round(wx * 1e4) / 1e4) + " x " +
                       mmv(std::round(wy * 1e4) / 1e4) + " mm) does not fit on a " + mmv(o.width_m) + " x " +
                       mmv(o.height_m) + " mm sheet with " + mmv(o.margin_m) + " mm margins; give a larger --sheet");
    // Lay long parts along the sheet's width when they fit so (rows of parts).
    bool rot = false;
    if (fit0 && fit90) rot = wy > wx;
    else rot = !fit0;
    items.push_back({i, rot ? wy : wx, rot ? wx : wy, rot, lo, hi});
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.h > b.h; });

  struct Shelf {
    int sheet;
    double y, h, x;
  };
  std::vector<Shelf> shelves;
  std::vector<double> sheet_top;  // used height per sheet
  Layout L;
  L.sheet = o;
  L.placements.resize(s.plates.size());
  for (const auto& it : items) {
    Shelf* sh = nullptr;
    for (auto& c : shelves)
      if (it.h <= c.h + 1e-12 && c.x + o.gap_m + it.w <= W + 1e-12) {
        sh = &c;
        break;
      }
    if (!sh) {
      int sheet = sheet_top.empty() ? -1 : static_cast<int>(sheet_top.size()) - 1;
      double y = 0;
      if (sheet >= 0) {
        y = sheet_top[sheet] + o.gap_m;
        if (y + it.h > H + 1e-12) sheet = -1;
      }
      if (sheet < 0) {
        sheet_top.push_back(0);
        sheet = static_cast<int>(sheet_top.size()) - 1;
        y = 0;
      }
      shelves.push_back({sheet, y, it.h, -o.gap_m});
      sheet_top[sheet] = y + it.h;
      sh = &shelves.back();
    }
    const double px = o.margin_m + sh->x + o.gap_m, py = o.margin_m + sh->y;
    sh->x += o.gap_m + it.w;
    Placement& pl = L.placements[it.i];
    pl.plate = it.i;
    pl.sheet = sh->sheet;
    pl.rotation_deg = it.rot ? 90 : 0;
    // rotation by +90 deg maps (u, v) to (-v, u): x in [-hi.y, -lo.y], y in [lo.x, hi.x]
    pl.offset = it.rot ? Vec2{px + it.hi.y, py - it.lo.x} : Vec2{px - it.lo.x, py - it.lo.y};
  }
  L.sheets = static_cast<int>(sheet_top.size());
  return L;
}

void write_dxf(const PlateSet& s, const Layout& l, const std::string& path) {
  const std::string tmp = temp_path_for(path);
  {
    DL_Dxf dxf;
    std::unique_ptr<DL_WriterA> dw(dxf.out(tmp.c_str(), DL_Codes::AC1015));
    if (!dw) throw InputError("cannot write '" + path + "': directory missing or not writable");
    // HEADER: dxflib writes $ACADVER and $HANDSEED; units are millimetres.
    dxf.writeHeader(*dw);
    dw->dxfString(9, "$INSUNITS");
    dw->dxfInt(70, 4);
    dw->dxfString(9, "$MEASUREMENT");
    dw->dxfInt(70, 1);
    dw->sectionEnd();

    dw->sectionTables();
    dxf.writeVPort(*dw);
    dw->tableLinetypes(3);
    dxf.writeLinetype(*dw, DL_LinetypeData("BYBLOCK", "", 0, 0, 0.0));
    dxf.writeLinetype(*dw, DL_LinetypeData("BYLAYER", "", 0, 0, 0.0));
    dxf.writeLinetype(*dw, DL_LinetypeData("CONTINUOUS", "Continuous", 0, 0, 0.0));
    dw->tableEnd();
    dw->tableLayers(4);
    dxf.writeLayer(*dw, DL_LayerData("0", 0), DL_Attributes("", 7, -1, 15, "CONTINUOUS"));
    dxf.writeLayer(*dw, DL_LayerData("CUT", 0), DL_Attributes("", 1, -1, 15, "CONTINUOUS"));
    dxf.writeLayer(*dw, DL_LayerData("ENGRAVE", 0), DL_Attributes("", 5, -1, 15, "CONTINUOUS"));
    dxf.writeLayer(*dw, DL_LayerData("SHEET", 0), DL_Attributes("", 8, -1, 15, "CONTINUOUS"));
    dw->tableEnd();
    dw->tableStyle(1);
    DL_StyleData style("Standard", 0, 0.0, 1.0, 0.0, 0, 2.5, "txt", "");
    style.bold = false;
    style.italic = false;
    dxf.writeStyle(*dw, style);
    dw->tableEnd();
    dxf.writeView(*dw);
    dxf.writeUcs(*dw);
    dw->tableAppid(1);
    dxf.writeAppid(*dw, "ACAD");
    dw->tableEnd();
    dxf.writeDimStyle(*dw, 2.5, 0.625, 0.625, 0.625, 2.5);
    dxf.writeBlockRecord(*dw);
    dw->tableEnd();
    dw->sectionEnd();

    dw->sectionBlocks();
    dxf.writeBlock(*dw, DL_BlockData("*Model_Space", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Model_Space");
    dxf.writeBlock(*dw, DL_BlockData("*Paper_Space", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Paper_Space");
    dxf.writeBlock(*dw, DL_BlockData("*Paper_Space0", 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(*dw, "*Paper_Space0");
    dw->sectionEnd();

    dw->sectionEntities();
    const DL_Attributes cut("CUT", 256, -1, -1, "BYLAYER");
    const DL_Attributes engrave("ENGRAVE", 256, -1, -1, "BYLAYER");
    const DL_Attributes sheet("SHEET", 256, -1, -1, "BYLAYER");
    auto polyline = [&](const Polygon& p, const DL_Attributes& at) {
      dxf.writePolyline(*dw, DL_PolylineData(static_cast<int>(p.size()), 0, 0, 1), at);
      for (const auto& v : p) dxf.writeVertex(*dw, DL_VertexData(v.x * 1000, v.y * 1000, 0.0, 0.0));
      dxf.writePolylineEnd(*dw);
    };
    auto text = [&](Vec2 c, double h, double angle_rad, const std::string& str, const DL_Attributes& at) {
      // centred on c (horizontal: centre, vertical: middle)
      dxf.writeText(*dw,
                    DL_TextData(c.x * 1000, c.y * 1000, 0, c.x * 1000, c.y * 1000, 0, h * 1000, 1.0, 0, 1, 2, str,
                                "Standard", angle_rad),
                    at);
    };
    auto line = [&](Vec2 a, Vec2 b) {
      dxf.writeLine(*dw, DL_LineData(a.x * 1000, a.y * 1000, 0, b.x * 1000, b.y * 1000, 0), engrave);
    };
    // Sheet borders and captions (not to be cut).
    for (int k = 0; k < l.sheets; ++k) {
      const double x0 = sheet_x_offset(l.sheet, k);
      polyline({{x0, 0}, {x0 + l.sheet.width_m, 0}, {x0 + l.sheet.width_m, l.sheet.height_m}, {x0, l.sheet.height_m}},
               sheet);
      char cap[256];
      std::snprintf(cap, sizeof cap, "%s: sheet %d of %d, %s x %s mm, %s mm thick", s.glider.c_str(), k + 1, l.sheets,
                    mmv(l.sheet.width_m).c_str(), mmv(l.sheet.height_m).c_str(), mmv(s.thickness_m).c_str());
      text({x0 + l.sheet.width_m / 2, l.sheet.height_m + 0.008}, 0.005, 0.0, cap, sheet);
    }
    // Engraving first, then holes, then outlines: parts stay in the sheet
    // until their last cut.
    for (const auto& pl : l.placements) {
      const Plate& p = s.plates[pl.plate];
      const Vec2 off{sheet_x_offset(l.sheet, pl.sheet), 0};
      auto P = [&](Vec2 q) { return place(pl, q) + off; };
      for (const auto& m : p.marks) {
        switch (m.kind) {
          case Mark::Kind::Line: line(P(m.points[0]), P(m.points[1])); break;
          case Mark::Kind::Cross: {
            const Vec2 c = m.points[0];
            line(P(c + Vec2{-m.size_m, 0}), P(c + Vec2{m.size_m, 0}));
            line(P(c + Vec2{0, -m.size_m}), P(c + Vec2{0, m.size_m}));
            break;
          }
          case Mark::Kind::Text:
          {
            // read from below or from the right, never upside down
            double a = std::fmod(m.angle_deg + pl.rotation_deg, 360.0);
            if (a < 0) a += 360;
            if (a > 90 + 1e-9 && a <= 270 + 1e-9) a -= 180;
            if (a > 270) a -= 360;
            text(P(m.points[0]), m.size_m, deg2rad(a), m.text, engrave);
          }
            break;
        }
      }
    }
    for (const auto& pl : l.placements) {
      const Plate& p = s.plates[pl.plate];
      const Vec2 off{sheet_x_offset(l.sheet, pl.sheet), 0};
      for (const auto& h : p.cut_holes) {
        Polygon q;
        for (const auto& v : h) q.push_back(place(pl, v) + off);
        polyline(q, cut);
      }
    }
    for (const auto& pl : l.placements) {
      const Plate& p = s.plates[pl.plate];
      const Vec2 off{sheet_x_offset(l.sheet, pl.sheet), 0};
      Polygon q;
      for (const auto& v : p.cut_outline) q.push_back(place(pl, v) + off);
      polyline(q, cut);
    }
    dw->sectionEnd();
    dxf.writeObjects(*dw);
    dxf.writeObjectsEnd(*dw);
    dw->dxfEOF();
    dw->close();
  }
  // dxflib does not report write errors: the file must end with its EOF marker.
  commit_temp_file(tmp, path, "EOF");
}

}  // namespace pteromys
