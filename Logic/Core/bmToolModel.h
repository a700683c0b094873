// bmToolModel.h - a rotating surgical tool as a solid of revolution with cutting edges.
//
// Tool frame T (Docs/Conventions.md section 1): origin on the axis at the tool's foremost cutting
// point, z_t along the axis from the tip toward the shank, feed along -z_t. A point at radial
// distance rho and axial height z is inside the tool when rho <= OuterRadius() and ZRange(rho)
// contains z. The time-averaged tool (lips spread over the revolution) is axisymmetric; the lips
// themselves are described by LipAzimuth() for the instantaneous option.
//
// Units: mm, radians; feed in mm/rev.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace bm {

/// What a part of the tool surface does.
enum class EdgeKind : unsigned char {
  None = 0,   ///< non-cutting surface (shank, margin, reamer back, guide nipple)
  Lip = 1,    ///< main cutting lip
  Chisel = 2, ///< chisel edge of a twist drill
};

/// Cutting angles of an edge element at radial distance r (radians), Docs/Model.md section 1.
struct CuttingAngles {
  double eps = 0;    ///< point angle: between the cutting edge and z_t
  double beta = 0;   ///< web angle
  double lambda = 0; ///< inclination angle
  double gammaN = 0; ///< normal rake angle
  double mu = 0;     ///< feed angle, atan(f / (2 pi r))
  double tau = 0;    ///< acos(sin eps cos beta / cos lambda)
};

/// One vertex of the tool's half-section outline in the (rho, z) plane.
struct ProfilePoint {
  double rho = 0;                 ///< mm
  double z = 0;                   ///< mm
  EdgeKind kind = EdgeKind::None; ///< kind of the outline from this vertex to the next
};

class ToolModel {
public:
  virtual ~ToolModel() = default;
  /// "drill", "reamer" or "burr".
  virtual std::string Kind() const = 0;
  /// Number of cutting lips N_c.
  virtual int NumLips() const = 0;
  /// Outermost radius of the tool, mm.
  virtual double OuterRadius() const = 0;
  /// Axial extent [zMin, zMax] of the tool, mm.
  virtual std::array<double, 2> AxialRange() const = 0;
  /// Inside interval of z at radial distance rho (mm); false when rho is outside the tool.
  virtual bool ZRange(double rho, double& zLo, double& zHi) const = 0;
  /// Radial range [rMin, rMax] (mm) of the cutting edges of the given kind; rMin == rMax if none.
  virtual std::array<double, 2> EdgeRange(EdgeKind kind) const = 0;
  /// Axial height (mm, tool frame) of the cutting edge of `kind` at radius r within EdgeRange.
  virtual double EdgeZ(EdgeKind kind, double r) const = 0;
  /// Cutting angles at radius r (mm) on an edge of the given kind, at feed f (mm/rev).
  /// useFeedAngle = false takes mu = 0 (Zheng et al.'s simplification on the lips).
  virtual CuttingAngles Angles(EdgeKind kind, double r, double feedMmPerRev,
                               bool useFeedAngle) const = 0;
  /// Azimuth (rad, tool frame, spindle angle 0) of lip `lip` at radius r: for the instantaneous
  /// lip.
  virtual double LipAzimuth(int lip, double r) const = 0;
  /// Half-section outline from the axis at the tip around to the axis at the back, sampled so
  /// that no segment is longer than maxSegmentMm. Used for the point shell and the display mesh.
  virtual std::vector<ProfilePoint> Profile(double maxSegmentMm) const = 0;
  /// Parameters as JSON (units in the key names' docs), and a copy with `params` applied.
  virtual nlohmann::json Parameters() const = 0;
  virtual std::unique_ptr<ToolModel> Clone() const = 0;
};

/// Twist drill, Docs/Model.md section 1; defaults = the reference drill (Lee et al. 2012).
/// Lips are straight, their projection offset w from the axis (web), point angle eps; they meet
/// the chisel edge (perpendicular to the axis) at the corner radius R_c = w / sin(psi) (Lazar &
/// Xirouchakis' geometry). Chisel: r in [0, R_c]; lips: r in [R_c, R]. Starting the lips at R_c
/// rather than at w keeps every lip element's torque resisting (within ~5 um of r = w, where
/// beta -> 90 deg, eq. 6 turns it negative). The swept tip is flat over the chisel and
/// z = cot(eps) (sqrt(rho^2 - w^2) - sqrt(R_c^2 - w^2)) over the lips.
struct TwistDrillParams {
  double radius = 1.25;          ///< R, mm
  double pointAngleDeg = 59.0;   ///< eps (half of the 118 deg point angle), deg
  double helixAngleDeg = 20.0;   ///< theta at the periphery, deg
  double chiselAngleDeg = 116.0; ///< psi, deg
  double webHalfWidth =
      0.2;      ///< w, half chisel-edge width, mm (not given by Lee et al.: a parameter)
  int lips = 2; ///< N_c
  double fluteLength = 10.0; ///< modelled length from the tip, mm
};

class TwistDrill final : public ToolModel {
public:
  explicit TwistDrill(const TwistDrillParams& p = {});
  const TwistDrillParams& Params() const { return P_; }
  std::string Kind() const override { return "drill"; }
  int NumLips() const override { return P_.lips; }
  double OuterRadius() const override { return P_.radius; }
  std::array<double, 2> AxialRange() const override { return {0.0, P_.fluteLength}; }
  bool ZRange(double rho, double& zLo, double& zHi) const override;
  std::array<double, 2> EdgeRange(EdgeKind kind) const override;
  double EdgeZ(EdgeKind, double r) const override { return TipHeight(r); }
  CuttingAngles Angles(EdgeKind kind, double r, double f, bool useFeedAngle) const override;
  double LipAzimuth(int lip, double r) const override;
  std::vector<ProfilePoint> Profile(double maxSegmentMm) const override;
  nlohmann::json Parameters() const override;
  std::unique_ptr<ToolModel> Clone() const override { return std::make_unique<TwistDrill>(P_); }
  /// Height of the tip surface above the chisel edge at radius rho, mm.
  double TipHeight(double rho) const;
  /// R_c = w / sin(psi): where the chisel edge meets the lips, mm.
  double ChiselCornerRadius() const;

private:
  TwistDrillParams P_;
};

/// Tool whose lips are circular arcs of radius R centred w from the axis (Docs/Model.md section 1):
/// eps = acos((r - w) / R), beta = asin(R sin(alpha) / r), gamma_n = rakeDeg (0 for the reamer).
/// Defaults = the spherical glenoid reamer of Faieghi et al. (5 lips, 36.5 mm, nipple guide).
/// Tool frame: z = 0 at the face's foremost ring (rho = w); the nipple reaches to -nippleLength.
/// With w = 0, alpha = 0 and no nipple it is a spherical burr of radius R.
struct ArcLipParams {
  double arcRadius = 16.22;      ///< R, mm
  double arcCentreOffset = 6.43; ///< w, mm
  double alphaDeg = 9.46;        ///< alpha, deg
  double rakeDeg = 0.0;          ///< gamma_n, deg
  double outerRadius = 18.25;    ///< lips end here (diameter 36.5 mm), mm
  int lips = 5;                  ///< N_c
  double nippleRadius = 3.0;     ///< central guide radius, mm (0 = none); does not cut
  double nippleLength = 6.0;     ///< guide protrusion beyond the face, mm
  double headThickness = 4.0;    ///< axial thickness of the head behind its rim, mm
  double shaftRadius = 4.0;      ///< shaft radius behind the head, mm
  double shaftLength = 20.0;     ///< modelled shaft length, mm
  std::string kind = "reamer";   ///< "reamer" or "burr"
};

class ArcLipTool final : public ToolModel {
public:
  explicit ArcLipTool(const ArcLipParams& p = {});
  /// A spherical burr of the given radius (mm) with `lips` flutes, no nipple, on a shaft.
  static ArcLipParams Burr(double radiusMm = 2.0, int lips = 8);
  const ArcLipParams& Params() const { return P_; }
  std::string Kind() const override { return P_.kind; }
  int NumLips() const override { return P_.lips; }
  double OuterRadius() const override;
  std::array<double, 2> AxialRange() const override;
  bool ZRange(double rho, double& zLo, double& zHi) const override;
  std::array<double, 2> EdgeRange(EdgeKind kind) const override;
  double EdgeZ(EdgeKind, double r) const override { return FaceHeight(r); }
  CuttingAngles Angles(EdgeKind kind, double r, double f, bool useFeedAngle) const override;
  double LipAzimuth(int lip, double r) const override;
  std::vector<ProfilePoint> Profile(double maxSegmentMm) const override;
  nlohmann::json Parameters() const override;
  std::unique_ptr<ToolModel> Clone() const override { return std::make_unique<ArcLipTool>(P_); }
  /// Axial height of the cutting face at radius rho (mm), tool frame.
  double FaceHeight(double rho) const;
  /// Radius where the lips begin (beyond the nipple and where beta is defined), mm.
  double LipInnerRadius() const;
  /// Axial height of the head's back (reamer plate, or where a burr's ball meets the shaft), mm.
  double BackHeight() const;

private:
  ArcLipParams P_;
};

/// Build a tool from JSON: {"type": "drill"|"reamer"|"burr", ...parameters}. Throws
/// std::invalid_argument naming the bad field.
std::unique_ptr<ToolModel> MakeTool(const nlohmann::json& spec);

} // namespace bm
