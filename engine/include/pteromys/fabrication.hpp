// Fabrication: flat plates with interlocking slots (docs/fabrication.md).
//
// A glider is built from one fuselage plate and one plate per wing (or two
// half plates when a wing is split). Where a wing crosses the fuselage the
// plates get slots whose geometry itself holds the wing at its mounting
// angle and position: the slot in the fuselage is tilted by the mounting
// angle Theta and sits on the wing's root chord. For every wing the engine
// chooses a joint that can physically be assembled (each part brought into
// place along a straight path without passing through material), or explains
// in plain words why none can.
//
// Frames (docs/theory.md, "Frames and signs"):
//  - fuselage plate: 2D coordinates (u, v) = glider (x, y); the plate occupies
//    w = z in [-t/2, t/2].
//  - wing plate: 2D coordinates (u, v) = the wing's own (x, z); glider point
//    = (x_m + u cos Theta + w sin Theta, y_m + u sin Theta - w cos Theta, v),
//    i.e. the w axis is d x e_z = (sin Theta, -cos Theta, 0) so that the frame
//    is right-handed; the plate occupies w in [-t/2, t/2].
//
// Geometry is computed with CGAL's exact kernel (Epeck) and Boolean set
// operations; results are returned in doubles. Units: metres, except names
// ending in _mm / _deg.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pteromys/glider.hpp"

namespace pteromys {

/// How a wing is joined to the fuselage.
enum class JointType {
  Auto,         ///< choose (through slot or notch, short cross-lap, halves, long cross-lap)
  ThroughSlot,  ///< closed tilted hole in the fuselage; the whole wing slides in spanwise
  Notch,        ///< the same slot open at the fuselage's edge (root chord reaching the edge); spanwise
  CrossLap,     ///< half slots in both plates along the root chord; the wing slides in along its chord
  Halves,       ///< closed hole in the fuselage; the wing split at z = 0, each half pushed in from its side
};
/// "auto", "through_slot", "notch", "cross_lap", "halves".
std::string joint_type_name(JointType t);
/// Inverse of joint_type_name; throws InputError naming the accepted words.
JointType joint_type_from_name(const std::string& s);

/// Manufacturing parameters.
struct FabricationOptions {
  /// Width of the laser beam's cut [m]. Cut paths are offset by kerf/2 away
  /// from the material (outlines outward, holes inward) so that finished parts
  /// have the design size. 0 <= kerf < slot width.
  double kerf_m = 0.0002;
  /// Slot width = thickness + clearance [m]; negative for a press fit
  /// (|clearance| < thickness). Closed holes are also longer than the wing's
  /// root chord by the clearance so that the wing slides.
  double clearance_m = 0.00005;
  /// Narrowest material allowed beside a slot [m] (>= 0).
  double min_web_m = 0.002;
  /// Sheet thickness used for slots and solids [m]; 0 = the glider file's
  /// material thickness. Mass properties always use the glider file.
  double thickness_m = 0.0;
  /// Joint per wing name (JointType::Auto or absent = choose). A key "*"
  /// applies to every wing not named.
  std::map<std::string, JointType> joints;
  /// Engraved text height for part names [m] (other labels are 3/4 of it).
  double text_height_m = 0.004;
};

/// Throws InputError when an option is not a finite number in its range.
void check_fabrication_options(const FabricationOptions& o, double thickness_m);

/// An engraved mark in a plate's own 2D frame [m].
struct Mark {
  enum class Kind { Line, Cross, Text };
  Kind kind = Kind::Line;
  /// Line: 2 points (a segment); Cross: 1 point (centre); Text: 1 point (the
  /// centre of the text's box).
  std::vector<Vec2> points;
  std::string text;        ///< Text: the string; Line/Cross: what it marks
  double size_m = 0.0;     ///< Text: height; Cross: half-length of each arm
  double angle_deg = 0.0;  ///< Text: direction of the baseline from the u axis
};
std::string mark_kind_name(Mark::Kind k);  ///< "line", "cross", "text"

/// A slot cut out of a plate: a rectangle in the plate's 2D frame [m],
/// counter-clockwise, possibly reaching beyond the plate (open slots).
struct Slot {
  std::string plate;     ///< name of the plate it is cut from
  std::string wing;      ///< the wing whose joint it belongs to
  Polygon rect;          ///< 4 corners, counter-clockwise (design size, no kerf)
  bool open = false;     ///< true when it opens to the plate's edge
  Vec2 axis_origin;      ///< centre of the closed end (one end of a closed hole)
  Vec2 axis_dir;         ///< unit vector along the slot (toward the opening)
  double length_m = 0;   ///< along axis_dir (open slots: reaches beyond the plate)
  /// Across axis_dir: thickness + clearance for slots along the root chord; for
  /// a piece of a hole opened to the plate's edge (axis across the chord), the
  /// length of chord it opens.
  double width_m = 0;
};

/// One wing-fuselage intersection and how it is built.
struct Joint {
  std::string wing;
  JointType type = JointType::Auto;
  /// Cross-lap: +1 the wing slides forward (toward +x of the wing) into a
  /// fuselage slot that opens behind it; -1 it slides backward. Through slot
  /// and halves: +1 the wing (right half) comes from +z.
  int direction = 0;
  /// Wing x (chord coordinate from the mount, [m]) where a cross-lap's two
  /// half slots meet or where the halves' root tabs change sides.
  double split_x_m = 0;
  /// Part of the root chord held by the joint: wing x interval [m].
  double engaged_from_m = 0, engaged_to_m = 0;
  std::vector<Slot> slots;  ///< every slot of this joint (fuselage and wing)
  std::string how;          ///< one plain sentence: how to assemble it
  /// Joint types tried before this one and why they were refused.
  std::vector<std::pair<JointType, std::string>> refused;
  int step = 0;  ///< position in the assembly order (1 = first wing in)
};

/// A finished plate.
struct Plate {
  std::string name;   ///< "fuselage", the wing's name, or "<wing> (right half)"
  std::string kind;   ///< "fuselage" or "wing"
  std::string wing;   ///< the wing's name (wing plates)
  std::string half;   ///< "", "right" (z > 0) or "left"
  std::string label;  ///< engraved name text
  /// Finished part (design size with slots): outline counter-clockwise,
  /// holes clockwise, in the plate's 2D frame [m].
  Polygon outline;
  std::vector<Polygon> holes;
  /// Laser path: outline offset outward and holes inward by kerf/2 [m].
  Polygon cut_outline;
  std::vector<Polygon> cut_holes;
  double thickness_m = 0;
  /// Row-major 4 x 4 matrix mapping plate (u, v, w, 1) to glider (x, y, z, 1) [m].
  std::array<double, 16> transform{};
  std::vector<Mark> marks;
  double area_m2 = 0;          ///< finished area (outline minus holes)
  double design_area_m2 = 0;   ///< area of the plate's outline in the glider file
  std::vector<std::size_t> joints;  ///< indices into PlateSet::joints
};

/// Every plate of a glider, the joints and the assembly order.
struct PlateSet {
  std::string glider;
  double thickness_m = 0;
  FabricationOptions options;
  std::vector<Plate> plates;         ///< fuselage first, then wings in file order
  std::vector<Joint> joints;         ///< one per wing, in file order
  std::vector<std::string> assembly; ///< plain-words steps in order
  std::vector<std::string> warnings;
};

/// Builds the slotted plates. Validates the glider first (InputError with the
/// validation problems). Throws InputError with a plain-words reason when a
/// wing cannot be joined (for example "no joint can hold wing 'main': ...").
PlateSet slotted_plates(const Glider& g, const FabricationOptions& o = {});

/// Kerf compensation of a region given as an outline (any orientation) and
/// holes: outline offset outward by r, holes inward by r (mitred corners,
/// CGAL straight skeleton). Returns {outline ccw, holes cw}. r >= 0 [m].
std::pair<Polygon, std::vector<Polygon>> offset_for_kerf(const Polygon& outline, const std::vector<Polygon>& holes,
                                                         double r);

/// Maps a plate point (u, v, w) to the glider frame with Plate::transform.
std::array<double, 3> plate_to_glider(const Plate& p, double u, double v, double w = 0.0);

/// Summary of a plate set as JSON (parts, joints with refused alternatives,
/// assembly steps, warnings); used by the command and the Python module.
nlohmann::json plates_summary(const PlateSet& s);

// ------------------------------------------------------------------ export

/// Sheets the DXF lays parts out on.
struct SheetOptions {
  double width_m = 0.600;   ///< along the DXF X axis
  double height_m = 0.900;  ///< along the DXF Y axis
  double margin_m = 0.005;  ///< free border of each sheet
  double gap_m = 0.004;     ///< free space between the cut paths of two parts
};

/// What `pteromys export` writes.
struct ExportRequest {
  FabricationOptions fabrication;
  SheetOptions sheet;
  std::string dxf_path;   ///< "" = no DXF
  std::string step_path;  ///< "" = no STEP
  /// STEP: one fused solid of the unslotted plates (prints in one piece)
  /// instead of one named solid per slotted plate.
  bool fused = false;
};

/// Builds the plates and writes the requested files (each atomically: a
/// failure leaves no partial file). Returns the summary of plates_summary
/// plus "sheets", "files" and "fused".
nlohmann::json export_glider(const Glider& g, const ExportRequest& r);

}  // namespace pteromys
