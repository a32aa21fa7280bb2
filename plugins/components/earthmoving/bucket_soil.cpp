// bucket-soil: the soil's resistance to a bucket's cutting edge, as a force
// on the edge (docs/soil.md). Three points on the bucket: `edge` (the cutting
// edge's middle), `heel` (a point of the floor behind it: the blade runs
// from heel to edge) and `side` (a point along the edge, so that up x (side -
// edge) is the direction the bucket cuts in). The ground is the plane z =
// ground_level (z up) or a height field (height_field.hpp) given by
// terrain_size, terrain_spacing, terrain_origin and terrain_heights. Below
// it the edge meets
//  - the cutting resistance of the fundamental earth-moving equation
//    (soil_cutting.hpp) at the edge's depth and the blade's rake angle, when
//    the edge moves forward along the cut: horizontal H = P sin(rho + delta)
//    + c_a w d cot(rho) against the cut, vertical V = P cos(rho + delta) -
//    c_a w d pulling the edge down;
//  - the bearing resistance of the edge's end (thickness t) when it is
//    pushed along the blade into the soil: w t (c N_c + gamma d N_q), its
//    cohesion's part set in over the same depth band as the depth itself.
// Both are smooth in depth, rake and speed (smooth.hpp), and their
// derivatives in the three points' positions and the edge's velocity are
// those of the same function, by forward-mode automatic differentiation.
// No states: the force is the whole coupling.
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <string>
#include <unsupported/Eigen/AutoDiff>
#include <utility>
#include <vector>

#include "components.hpp"
#include "example_models.hpp"
#include "height_field.hpp"
#include "monohydra/cpp/checked_options.hpp"
#include "monohydra/cpp/services.hpp"
#include "scalar.hpp"
#include "smooth.hpp"
#include "soil_cutting.hpp"

namespace earth {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The rake angles the equation is used in: a blade flatter than 10 degrees
// would bulldoze along its own length (cot rho -> infinity), one steeper
// than 80 degrees is the bucket's back; rounded off over 5 degrees.
constexpr double kRakeLow = 10.0 * kDegree, kRakeHigh = 80.0 * kDegree, kRakeBand = 5.0 * kDegree;

// The points' coordinates and the edge's velocity: what the force depends on.
constexpr int kInputs = 12;
using Dual = Eigen::AutoDiffScalar<Eigen::Matrix<double, kInputs, 1>>;

// What the soil does to the edge, and why (the outputs).
template <class S>
struct EdgeForce {
  S force[3];                  // on the edge, N, world
  S horizontal, vertical;      // H and V times the cut's mobilisation
  S penetration;               // the edge end's bearing force
  double depth = 0.0;          // m below the ground
  double rake = 0.0;           // rad, before the clamp
  double failure_angle = 0.0;  // rad
};

class BucketSoil {
 public:
  static const mh_component_descriptor kDescriptor;
  static constexpr const char* kExampleModel = kBladeExample;  // example_models.hpp

  explicit BucketSoil(const mh_host* host) : host_(host) {}

  mh_status setup() {
    const mh_host* h = host_;
    if (read_soil() != MH_OK) return MH_ERROR;
    if (monohydra::positive_option(h, "width", 1, 0.0, "a positive cutting width (m)", &width_) !=
            MH_OK ||
        monohydra::nonnegative_option(h, "edge_thickness", 0, 0.02,
                                      "a non-negative thickness of the edge (m)",
                                      &thickness_) != MH_OK ||
        monohydra::options(h).option_number(h, "ground_level", 0, kNaN, &ground_) != MH_OK ||
        monohydra::positive_option(h, "depth_band", 0, 0.005,
                                   "a positive depth over which the force sets in (m)",
                                   &depth_band_) != MH_OK ||
        monohydra::positive_option(h, "speed_scale", 0, 0.01,
                                   "a positive speed over which the resistance is mobilised (m/s)",
                                   &speed_scale_) != MH_OK)
      return MH_ERROR;
    if (read_terrain() != MH_OK) return MH_ERROR;
    const auto& points = monohydra::subsystem_setup(h);
    if (points.add_point(h, "edge", &edge_) != MH_OK ||
        points.add_point(h, "heel", &heel_) != MH_OK ||
        points.add_point(h, "side", &side_) != MH_OK)
      return MH_ERROR;
    double e[3], hp[3], sp[3];
    if (points.point_position(h, edge_, e) != MH_OK ||
        points.point_position(h, heel_, hp) != MH_OK ||
        points.point_position(h, side_, sp) != MH_OK)
      return MH_ERROR;
    if (std::hypot(hp[0] - e[0], hp[1] - e[1], hp[2] - e[2]) < 1e-3)
      return monohydra::options(h).option_error(
          h, "points",
          "a heel point at least 1 mm from the edge (the blade runs from heel to edge)");
    if (std::hypot(sp[0] - e[0], sp[1] - e[1]) < 1e-3)
      return monohydra::options(h).option_error(
          h, "points",
          "a side point at least 1 mm from the edge horizontally (the edge's lateral axis; up x "
          "(side - edge) is the direction of the cut)");
    const BearingFactors b = bearing_factors(soil_.friction_angle);
    bearing_c_ = b.cohesion;
    bearing_q_ = b.depth;
    static constexpr const char* kNames[7] = {"Fh", "Fv", "Fp", "depth", "rake", "beta", "power"};
    static constexpr const char* kUnits[7] = {"N", "N", "N", "m", "rad", "rad", "W"};
    for (int i = 0; i < 7; ++i) {
      const mh_output_spec spec = monohydra::output_spec(kNames[i], kUnits[i]);
      if (monohydra::outputs(h).add_output(h, &spec, &out_[i]) != MH_OK) return MH_ERROR;
    }
    return MH_OK;
  }

  mh_status evaluate(const mh_subsystem_eval& eval) const {
    double in[kInputs];
    if (!inputs(eval, in)) return degenerate();
    EdgeForce<double> f;
    edge_force(in, f);
    for (int i = 0; i < 3; ++i) eval.point_f[3 * edge_ + i] += f.force[i];
    const double values[7] = {f.horizontal, f.vertical,      f.penetration,   f.depth,
                              f.rake,       f.failure_angle, power(f, in + 9)};
    for (int i = 0; i < 7; ++i) eval.outputs[out_[i]] = values[i];
    return MH_OK;
  }

  // d(force on the edge)/d(the points' positions, velocities), 9 x 9
  // column-major (rows: the force on each point; columns: each point's
  // coordinates): the edge's rows alone are nonzero.
  mh_status point_force_jacobian(const mh_subsystem_eval& eval, double* dF_dp,
                                 double* dF_dv) const {
    double in[kInputs];
    if (!inputs(eval, in)) return MH_DISCARD;
    Dual x[kInputs];
    for (int k = 0; k < kInputs; ++k) x[k] = Dual(in[k], kInputs, k);
    EdgeForce<Dual> f;
    edge_force(x, f);
    constexpr int kRows = 9;
    const int point[3] = {edge_, heel_, side_};
    for (int i = 0; i < 3; ++i) {
      const int row = 3 * edge_ + i;
      for (int p = 0; p < 3; ++p)
        for (int j = 0; j < 3; ++j)
          dF_dp[(3 * point[p] + j) * kRows + row] += f.force[i].derivatives()[3 * p + j];
      for (int j = 0; j < 3; ++j)
        dF_dv[(3 * edge_ + j) * kRows + row] += f.force[i].derivatives()[9 + j];
    }
    return MH_OK;
  }

  mh_status coupling_jacobian(const mh_subsystem_eval&, double*, double*, double*, double*) const {
    return MH_OK;  // no states
  }

  // Nothing stored; what the edge does to the soil, -F . v, goes into it
  // (cutting, bearing): the balance's dissipation.
  mh_status energy(const mh_subsystem_eval& eval, double& stored, double& dissipation) const {
    double in[kInputs];
    if (!inputs(eval, in)) return MH_DISCARD;
    EdgeForce<double> f;
    edge_force(in, f);
    stored = 0.0;
    dissipation = power(f, in + 9);
    return MH_OK;
  }

 private:
  mh_status read_soil() {
    const mh_host* h = host_;
    if (monohydra::positive_option(h, "density", 1, 0.0, "a positive soil density (kg/m^3)",
                                   &soil_.density) != MH_OK ||
        monohydra::positive_option(h, "gravity", 0, 9.81,
                                   "a positive acceleration of gravity (m/s^2)",
                                   &soil_.gravity) != MH_OK ||
        monohydra::nonnegative_option(h, "cohesion", 0, 0.0, "a non-negative cohesion (Pa)",
                                      &soil_.cohesion) != MH_OK ||
        monohydra::nonnegative_option(h, "adhesion", 0, 0.0, "a non-negative adhesion (Pa)",
                                      &soil_.adhesion) != MH_OK ||
        monohydra::nonnegative_option(h, "surcharge", 0, 0.0,
                                      "a non-negative surcharge pressure (Pa)",
                                      &soil_.surcharge) != MH_OK)
      return MH_ERROR;
    const auto& o = monohydra::options(host_);
    if (o.option_number(h, "friction_angle", 1, 0.0, &soil_.friction_angle) != MH_OK ||
        o.option_number(h, "interface_friction", 0, -1.0, &soil_.interface_friction) != MH_OK)
      return MH_ERROR;
    const double phi = soil_.friction_angle;
    if (!(phi >= 0.0 && phi < 0.5 * kPi))
      return o.option_error(h, "friction_angle",
                            "an internal friction angle phi with 0 <= phi < pi/2 rad (90 degrees)");
    if (soil_.interface_friction < 0.0) soil_.interface_friction = (2.0 / 3.0) * phi;
    const double delta = soil_.interface_friction;
    if (!(delta >= 0.0 && delta <= phi))
      return o.option_error(h, "interface_friction",
                            "a soil-metal friction angle delta with 0 <= delta <= friction_angle "
                            "(rad; default 2/3 of it)");
    // At the steepest rake used (80 degrees) the wedge must still fail on a
    // plane: rho + delta + beta + phi < pi for some beta of at least 5 degrees.
    if (!(phi + delta < kPi - kRakeHigh - 5.0 * kDegree))
      return o.option_error(h, "interface_friction",
                            "friction_angle + interface_friction below 95 degrees (1.658 rad)");
    return MH_OK;
  }

  // The ground: the plane z = ground_level (0 by default), or a height
  // field of terrain_size [nx, ny] points terrain_spacing apart from
  // terrain_origin [x0, y0], terrain_heights its ny rows of nx heights.
  mh_status read_terrain() {
    const mh_host* h = host_;
    const auto& o = monohydra::options(h);
    const double* size = nullptr;
    uint32_t rows = 0;
    if (o.option_table(h, "terrain_size", 0, 2, &size, &rows) != MH_OK) return MH_ERROR;
    if (size == nullptr || rows == 0) {
      if (std::isnan(ground_)) ground_ = 0.0;
      if (!std::isfinite(ground_))
        return o.option_error(h, "ground_level", "the ground's height (m), a finite number");
      return MH_OK;
    }
    if (!std::isnan(ground_))
      return o.option_error(h, "ground_level",
                            "either a ground_level or a terrain (terrain_size), not both");
    const auto whole = [](double v) { return v >= 2.0 && v <= 1e6 && v == std::floor(v); };
    if (rows != 1 || !whole(size[0]) || !whole(size[1]))
      return o.option_error(h, "terrain_size",
                            "[nx, ny]: whole numbers of grid points along x and y, each at least "
                            "2 (a grid of at least one cell)");
    const int nx = static_cast<int>(size[0]), ny = static_cast<int>(size[1]);
    double spacing = 0.0;
    if (monohydra::positive_option(h, "terrain_spacing", 1, 0.0,
                                   "a positive distance between the terrain's grid points (m)",
                                   &spacing) != MH_OK)
      return MH_ERROR;
    const double* origin = nullptr;
    if (o.option_table(h, "terrain_origin", 0, 2, &origin, &rows) != MH_OK) return MH_ERROR;
    if (origin != nullptr && (rows != 1 || !std::isfinite(origin[0]) || !std::isfinite(origin[1])))
      return o.option_error(h, "terrain_origin", "[x0, y0]: the grid's first point (m)");
    const double* heights = nullptr;
    if (o.option_table(h, "terrain_heights", 1, static_cast<uint32_t>(nx), &heights, &rows) !=
        MH_OK)
      return MH_ERROR;
    const std::string rows_expected = std::to_string(ny) + " rows (terrain_size's ny) of " +
                                      std::to_string(nx) +
                                      " finite heights (m), row j at y0 + j terrain_spacing";
    if (rows != static_cast<uint32_t>(ny))
      return o.option_error(h, "terrain_heights", rows_expected.c_str());
    std::vector<double> z(heights, heights + static_cast<size_t>(nx) * static_cast<size_t>(ny));
    for (const double v : z)
      if (!std::isfinite(v)) return o.option_error(h, "terrain_heights", rows_expected.c_str());
    terrain_ = HeightField(origin == nullptr ? 0.0 : origin[0], origin == nullptr ? 0.0 : origin[1],
                           spacing, nx, ny, std::move(z));
    has_terrain_ = true;
    return MH_OK;
  }

  // What the edge at velocity v does to the soil, -F . v (W).
  static double power(const EdgeForce<double>& f, const double* v) {
    return -(f.force[0] * v[0] + f.force[1] * v[1] + f.force[2] * v[2]);
  }

  // The edge's, heel's and side's positions and the edge's velocity; false
  // when the blade or the edge's lateral axis has no direction.
  bool inputs(const mh_subsystem_eval& eval, double* in) const {
    const int point[3] = {edge_, heel_, side_};
    for (int p = 0; p < 3; ++p)
      for (int j = 0; j < 3; ++j) in[3 * p + j] = eval.point_p[3 * point[p] + j];
    for (int j = 0; j < 3; ++j) in[9 + j] = eval.point_v[3 * edge_ + j];
    const double blade = std::hypot(in[3] - in[0], in[4] - in[1], in[5] - in[2]);
    const double lateral = std::hypot(in[6] - in[0], in[7] - in[1]);
    return blade > 1e-9 && lateral > 1e-9;
  }

  mh_status degenerate() const {
    host_->log(host_, MH_LOG_ERROR,
               "bucket-soil: the heel meets the edge, or the side is straight above it: the blade "
               "has no direction");
    return MH_ERROR;
  }

  template <class S>
  void edge_force(const S* in, EdgeForce<S>& f) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    using std::sqrt;
    using std::tan;
    const S* e = in;
    const S* heel = in + 3;
    const S* side = in + 6;
    const S* v = in + 9;
    // The cut's direction m = up x lateral, horizontal; the blade u from the
    // edge back to the heel; the rake is u's angle above -m.
    const S lx = side[0] - e[0], ly = side[1] - e[1];
    const S lateral = sqrt(lx * lx + ly * ly);
    const S m[3] = {-ly / lateral, lx / lateral, S(0.0) * lx};
    const S u[3] = {heel[0] - e[0], heel[1] - e[1], heel[2] - e[2]};
    const S back = -(u[0] * m[0] + u[1] * m[1]);
    const S rake = atan2(u[2], back);
    const S depth =
        (has_terrain_ ? terrain_.height<S>(e[0], e[1]) : S(ground_) + S(0.0) * e[0]) - e[2];
    const S d = ramp<S>(depth, depth_band_);
    const S rho = soft_clamp<S>(rake, kRakeLow, kRakeHigh, kRakeBand);
    f.depth = value(depth);
    f.rake = value(rake);
    const double delta = soil_.interface_friction;
    f.failure_angle = value(d) > 0.0 ? failure_angle(soil_, value(d), value(rho)) : 0.0;
    const S p = width_ * force_per_width(soil_, d, rho, value(d) > 0.0 ? f.failure_angle : 1.0);
    const S adhesion = soil_.adhesion * width_ * d;
    const S h = p * sin(rho + delta) + adhesion * cos(rho) / sin(rho);
    const S vertical = p * cos(rho + delta) - adhesion;
    const S cut = mobilised<S>(v[0] * m[0] + v[1] * m[1], speed_scale_);
    // The bearing force along the blade, towards the heel, when the edge is
    // pushed along it into the soil.
    const S blade = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    const S along = -(v[0] * u[0] + v[1] * u[1] + v[2] * u[2]) / blade;
    const S bearing = mobilised<S>(along, speed_scale_) * width_ * thickness_ *
                      (soil_.cohesion * bearing_c_ * engaged<S>(depth, depth_band_) +
                       soil_.density * soil_.gravity * bearing_q_ * d);
    f.horizontal = cut * h;
    f.vertical = cut * vertical;
    f.penetration = bearing;
    for (int i = 0; i < 2; ++i) f.force[i] = -f.horizontal * m[i] + bearing * u[i] / blade;
    f.force[2] = -f.vertical + bearing * u[2] / blade;
  }

  const mh_host* host_;
  Soil soil_;
  HeightField terrain_;
  bool has_terrain_ = false;
  double width_ = 0.0, thickness_ = 0.0, ground_ = 0.0, depth_band_ = 0.0, speed_scale_ = 0.0;
  double bearing_c_ = 0.0, bearing_q_ = 0.0;
  int32_t edge_ = -1, heel_ = -1, side_ = -1;
  int32_t out_[7] = {-1, -1, -1, -1, -1, -1, -1};
};

const mh_component_descriptor BucketSoil::kDescriptor{
    sizeof(mh_component_descriptor),
    "bucket-soil",
    "Soil cutting at a bucket's edge",
    "monohydra",
    "1.0.0",
    "The fundamental earth-moving equation's cutting resistance (McKyes 1985) and the edge's "
    "bearing resistance, on point edge, below the ground (the plane z = ground_level, or a "
    "terrain height field); the blade runs from point heel to edge, the cut along up x (side - "
    "edge). Options: width (m), density "
    "(kg/m^3), friction_angle and interface_friction (rad), cohesion, adhesion, surcharge (Pa), "
    "edge_thickness (m, default 0.02), ground_level (m, default 0) or terrain_size [nx, ny], "
    "terrain_spacing (m), terrain_origin [x0, y0] (m), terrain_heights (ny rows of nx, m), "
    "gravity (m/s^2, default "
    "9.81), depth_band (m, default 0.005), speed_scale (m/s, default 0.01). Outputs Fh, Fv, Fp "
    "(N), depth (m), rake, beta (rad), power (W)."};

}  // namespace

const monohydra::SubsystemComponent kBucketSoil = monohydra::subsystem_component<BucketSoil>();

}  // namespace earth
