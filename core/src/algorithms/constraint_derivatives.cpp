// Analytic derivatives of the cut-joint terms (Sects. 2.2-2.3): the Hessians of
// the constraints contracted with a vector (the tangent of Eq. 18's
// Phi_z^T (alpha Phi + lambda)) and the derivatives of the constraint
// accelerations (Eqs. 15, 21), for Newton tangents without finite differences.
// Every row of constraints.hpp is a product x . y of a vector x fixed on a body
// (n on its frame, or c on body a) and a point difference or a vector fixed on
// another body, so one product rule over the tree variations of
// motion_variation.hpp serves every joint type.
#include "monohydra/core/constraint_derivatives.hpp"

#include <stdexcept>
#include <string>

#include "algorithms/motion_variation.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {
namespace {

using detail::BodyVariation;
using detail::PointMotion;

[[noreturn]] void throw_size(const char* where, const char* what, Eigen::Index expected,
                             Eigen::Index got) {
  throw std::invalid_argument(std::string(where) + ": " + what + ": expected " +
                              std::to_string(expected) + ", got " + std::to_string(got));
}

void check_common(const char* where, const Model& model, const Data& data,
                  const ConstraintDerivativesWorkspace& ws) {
  const int n = model.num_coordinates();
  if (static_cast<int>(data.R_W_B.size()) != n) {
    throw_size(where, "data (bodies)", n, static_cast<Eigen::Index>(data.R_W_B.size()));
  }
  if (static_cast<int>(ws.Zdot.size()) != n) {
    throw_size(where, "workspace (bodies)", n, static_cast<Eigen::Index>(ws.Zdot.size()));
  }
}

// One factor of a row's product: a point (moves with the twist's velocity
// field) or a vector (turns with its angular part) fixed on `body`.
struct Factor {
  int body = kGround;
  bool is_point = true;
  Eigen::Vector3d local = Eigen::Vector3d::Zero();  // body frame
};

Eigen::Vector3d world_of(const Data& data, const Factor& f) {
  const BodyPoint bp{f.body, f.local};
  if (f.is_point) return point_position(data, bp);
  return body_rotation(data, f.body) * f.local;
}

// Change of the factor's world value q for the geometric twist t of a body below.
Eigen::Vector3d displace(const Factor& f, const Vector6d& t, const Eigen::Vector3d& q) {
  return f.is_point ? detail::twist_at(t, q) : Eigen::Vector3d(t.tail<3>().cross(q));
}

// The row as sign_i (x_i . y_i) for two terms i (a point row's n . p_b - n . p_a,
// a dot row's c . d with an empty second term).
struct RowTerms {
  Factor x[2], y[2];
  double sign[2] = {1.0, -1.0};
  int count = 1;
};

RowTerms terms_of(const ConstraintRow& row) {
  RowTerms t;
  if (row.kind == ConstraintRow::Kind::point) {
    t.count = 2;
    for (int i = 0; i < 2; ++i) t.x[i] = Factor{row.frame, false, row.n};
    t.y[0] = Factor{row.b.body, true, row.b.p_B};
    t.y[1] = Factor{row.a.body, true, row.a.p_B};
  } else {
    t.x[0] = Factor{row.a.body, false, row.c};
    t.y[0] = Factor{row.b.body, false, row.d};
  }
  return t;
}

// Adds s * d^2(x . y)/dz_k dz_l over the coordinates k, l on the factors' paths.
// A displacement by b_k then b_l (both on one path, the ancestor a, the
// descendant e) gives w_a x (b_e at q): the second variation of
// motion_variation.hpp's b_e -> b_e + b_a x b_e.
void add_product_hessian(const Model& model, const Data& data, const Factor& x, const Factor& y,
                         double s, ConstraintDerivativesWorkspace& ws,
                         Eigen::Ref<Eigen::MatrixXd> out) {
  detail::mark_path(model, x.body, ws.mask_x);
  detail::mark_path(model, y.body, ws.mask_y);
  int count = 0;
  for (int k = 0; k < model.num_coordinates(); ++k) {
    if (ws.mask_x[k] || ws.mask_y[k]) ws.coordinates[count++] = k;
  }
  const Eigen::Vector3d xw = world_of(data, x), yw = world_of(data, y);
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  for (int a = 0; a < count; ++a) {
    const int k = ws.coordinates[a];
    const Eigen::Vector3d dx_k = ws.mask_x[k] ? displace(x, data.b[k], xw) : zero;
    const Eigen::Vector3d dy_k = ws.mask_y[k] ? displace(y, data.b[k], yw) : zero;
    for (int c = a; c < count; ++c) {  // l >= k: k is the ancestor when both are on one path
      const int l = ws.coordinates[c];
      const Eigen::Vector3d wk = data.b[k].tail<3>();
      const Eigen::Vector3d dx_l = ws.mask_x[l] ? displace(x, data.b[l], xw) : zero;
      const Eigen::Vector3d dy_l = ws.mask_y[l] ? displace(y, data.b[l], yw) : zero;
      const Eigen::Vector3d ddx =
          ws.mask_x[k] && ws.mask_x[l] ? Eigen::Vector3d(wk.cross(dx_l)) : zero;
      const Eigen::Vector3d ddy =
          ws.mask_y[k] && ws.mask_y[l] ? Eigen::Vector3d(wk.cross(dy_l)) : zero;
      const double value = s * (ddx.dot(yw) + dx_k.dot(dy_l) + dx_l.dot(dy_k) + xw.dot(ddy));
      out(k, l) += value;
      if (l != k) out(l, k) += value;
    }
  }
}

// A factor's world value and its first and second time derivatives.
PointMotion motion_of(const Data& data, const ConstraintDerivativesWorkspace& ws, const Factor& f) {
  const Eigen::Vector3d q = world_of(data, f);
  const Vector6d Z = f.body == kGround ? Vector6d::Zero() : data.Z[f.body];
  const Vector6d Zd = f.body == kGround ? Vector6d::Zero() : ws.Zdot[f.body];
  return f.is_point ? detail::point_motion(q, Z, Zd) : detail::vector_motion(q, Z, Zd);
}

PointMotion vary(const Data& data, const ConstraintDerivativesWorkspace& ws, const Factor& f,
                 const PointMotion& m, int k, bool rate) {
  const BodyVariation dv =
      rate ? detail::variation_zd(data, f.body, k) : detail::variation_z(data, ws.Zdot, f.body, k);
  const Vector6d& Z = data.Z[f.body];
  const Vector6d& Zd = ws.Zdot[f.body];
  return f.is_point ? detail::vary_point(m, Z, Zd, dv) : detail::vary_vector(m, Z, Zd, dv);
}

// (x . y)'' = xdd . y + 2 xd . yd + x . ydd: A of one row (Eq. 15's Phi_z zdd + Phi_z_dot zd).
double second_rate(const PointMotion& x, const PointMotion& dx, const PointMotion& y,
                   const PointMotion& dy) {
  return dx.a.dot(y.p) + x.a.dot(dy.p) + 2.0 * (dx.v.dot(y.v) + x.v.dot(dy.v)) + dx.p.dot(y.a) +
         x.p.dot(dy.a);
}

}  // namespace

ConstraintDerivativesWorkspace::ConstraintDerivativesWorkspace(const Model& model) {
  const auto nb = static_cast<std::size_t>(model.num_bodies());
  Zdot.assign(nb, Vector6d::Zero());
  mask_x.assign(nb, 0);
  mask_y.assign(nb, 0);
  mask_z.assign(nb, 0);
  coordinates.assign(nb, 0);
}

void constraint_force_derivative(const Model& model, const Data& data,
                                 const Constraints& constraints, const Eigen::VectorXd& v,
                                 ConstraintDerivativesWorkspace& ws,
                                 Eigen::Ref<Eigen::MatrixXd> dPhizTv_dz) {
  const char* where = "constraint_force_derivative";
  check_common(where, model, data, ws);
  const int n = model.num_coordinates();
  if (v.size() != constraints.size()) throw_size(where, "v", constraints.size(), v.size());
  if (dPhizTv_dz.rows() != n || dPhizTv_dz.cols() != n) {
    throw_size(where, "dPhizTv_dz rows and columns", n, dPhizTv_dz.rows());
  }
  dPhizTv_dz.setZero();
  for (int i = 0; i < constraints.size(); ++i) {
    if (v[i] == 0.0) continue;
    const RowTerms t = terms_of(constraints.rows[static_cast<std::size_t>(i)]);
    for (int j = 0; j < t.count; ++j) {
      add_product_hessian(model, data, t.x[j], t.y[j], v[i] * t.sign[j], ws, dPhizTv_dz);
    }
  }
}

void constraint_acceleration_derivatives(const Model& model, const Data& data,
                                         const Constraints& constraints, const Eigen::VectorXd& zdd,
                                         ConstraintDerivativesWorkspace& ws,
                                         Eigen::Ref<Eigen::MatrixXd> dA_dz,
                                         Eigen::Ref<Eigen::MatrixXd> dA_dzd) {
  const char* where = "constraint_acceleration_derivatives";
  check_common(where, model, data, ws);
  const int n = model.num_coordinates();
  const int m = constraints.size();
  if (zdd.size() != n) throw_size(where, "zdd", n, zdd.size());
  if (dA_dz.rows() != m || dA_dz.cols() != n) throw_size(where, "dA_dz rows", m, dA_dz.rows());
  if (dA_dzd.rows() != m || dA_dzd.cols() != n) {
    throw_size(where, "dA_dzd rows", m, dA_dzd.rows());
  }
  // Full Zdot_j = Zdot_parent + b_j zdd_j + d_j (Eqs. 3, 5).
  for (int j = 0; j < n; ++j) {
    const int p = model.bodies[j].parent;
    ws.Zdot[j] = (p == kGround ? Vector6d::Zero() : ws.Zdot[p]) + data.b[j] * zdd[j] + data.d[j];
  }
  dA_dz.setZero();
  dA_dzd.setZero();
  for (int i = 0; i < m; ++i) {
    const RowTerms t = terms_of(constraints.rows[static_cast<std::size_t>(i)]);
    // One x for both terms; y = sign_0 y_0 + sign_1 y_1 (a point row's r = p_b - p_a).
    const Factor& x = t.x[0];
    const PointMotion xm = motion_of(data, ws, x);
    PointMotion ym[2];
    PointMotion y{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    for (int j = 0; j < t.count; ++j) {
      ym[j] = motion_of(data, ws, t.y[j]);
      y.p += t.sign[j] * ym[j].p;
      y.v += t.sign[j] * ym[j].v;
      y.a += t.sign[j] * ym[j].a;
    }
    detail::mark_path(model, x.body, ws.mask_x);
    detail::mark_path(model, t.y[0].body, ws.mask_y);
    detail::mark_path(model, t.count > 1 ? t.y[1].body : kGround, ws.mask_z);
    const std::vector<char>* masks[2] = {&ws.mask_y, &ws.mask_z};
    for (int k = 0; k < n; ++k) {
      if (!ws.mask_x[k] && !ws.mask_y[k] && !ws.mask_z[k]) continue;
      for (int pass = 0; pass < 2; ++pass) {
        const bool rate = pass == 1;
        const PointMotion zero{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                               Eigen::Vector3d::Zero()};
        const PointMotion dx = ws.mask_x[k] ? vary(data, ws, x, xm, k, rate) : zero;
        PointMotion dy = zero;
        for (int j = 0; j < t.count; ++j) {
          if (!(*masks[j])[k]) continue;
          const PointMotion d = vary(data, ws, t.y[j], ym[j], k, rate);
          dy.p += t.sign[j] * d.p;
          dy.v += t.sign[j] * d.v;
          dy.a += t.sign[j] * d.a;
        }
        (rate ? dA_dzd : dA_dz)(i, k) = second_rate(xm, dx, y, dy);
      }
    }
  }
}

}  // namespace mh
