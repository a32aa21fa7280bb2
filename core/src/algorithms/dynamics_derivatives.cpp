// Analytic K = d(M' zdd - Q')/dz and C = d(M' zdd - Q')/dzd of the open-loop
// semirecursive dynamics (Sect. 2.1, Eqs. 1-12), for the Newton tangent of
// implicit steps without finite differences. Written as the inverse dynamics
//   M' zdd - Q' = R_d^T T^T (Mbar T (R_d zdd + Rdot_d zd) - Qbar)      (Eqs. 5, 11, 12)
// i.e. residual_i = b_i . H_i with H_i the sum over the subtree of body i of
// h_j = Mbar_j Zdot_j - Qbar_j, and differentiated body by body with the tree
// variations of motion_variation.hpp, factored so that each body contributes
// 6 x 6 matrices once (O(N)) and each entry of K and C costs a few dot products
// (O(N x depth) entries; see fill_columns_factored) on deep trees, or swept one
// subtree per coordinate (O(sum of depths) body variations) on shallow ones.
#include "monohydra/core/dynamics_derivatives.hpp"

#include <stdexcept>
#include <string>

#include "algorithms/motion_variation.hpp"
#include "monohydra/core/kinematics.hpp"

namespace mh {
namespace {

using detail::BodyVariation;
using detail::motion_cross;
using detail::twist_at;

[[noreturn]] void throw_size(const char* what, Eigen::Index expected, Eigen::Index got) {
  throw std::invalid_argument(std::string("dynamics_derivatives: ") + what + ": expected " +
                              std::to_string(expected) + ", got " + std::to_string(got));
}

void check_sizes(const Model& model, const Data& data, const Eigen::VectorXd& zdd,
                 const DynamicsDerivativesWorkspace& ws, const Eigen::Ref<Eigen::MatrixXd>& K,
                 const Eigen::Ref<Eigen::MatrixXd>& C) {
  const int n = model.num_coordinates();
  if (static_cast<int>(data.R_W_B.size()) != n) {
    throw_size("data (bodies)", n, static_cast<Eigen::Index>(data.R_W_B.size()));
  }
  if (static_cast<int>(ws.h.size()) != n) {
    throw_size("workspace (bodies)", n, static_cast<Eigen::Index>(ws.h.size()));
  }
  if (zdd.size() != n) throw_size("zdd", n, zdd.size());
  if (K.rows() != n || K.cols() != n) throw_size("K rows and columns", n, K.rows());
  if (C.rows() != n || C.cols() != n) throw_size("C rows and columns", n, C.rows());
}

// The body's share of the residual and its variation, in Newton-Euler form.
// With A = a + alpha x g (the COM acceleration less its velocity term omega x gdot),
//   Mbar Zdot = [m A; g x m A + J alpha]                      (Eq. 9)
//   Qbar      = [f - m omega x gdot; g x (f - m omega x gdot) - omega x J omega]  (Eq. 10)
// so h = [F; g x F + T] with F = m (A + omega x gdot) - f, T = J alpha + omega x J omega.
struct BodyState {
  double m;
  Eigen::Vector3d g, gdot, omega, alpha, F;
  Eigen::Matrix3d J;
  Eigen::Vector3d Jw, Ja;  // J omega, J alpha
};

Vector6d body_residual(const BodyState& s, const Vector6d& Zdot, const Eigen::Vector3d& weight) {
  const Eigen::Vector3d A = Zdot.head<3>() + s.alpha.cross(s.g);
  const Eigen::Vector3d F = s.m * (A + s.omega.cross(s.gdot)) - weight;
  const Eigen::Vector3d T = s.J * s.alpha + s.omega.cross(s.J * s.omega);
  Vector6d h;
  h << F, s.g.cross(F) + T;
  return h;
}

// d h for the body's variation dv (geometry moved by dv.twist, Z and Zdot changed).
Vector6d vary_body_residual(const BodyState& s, const BodyVariation& dv) {
  const Eigen::Vector3d w = dv.twist.tail<3>();
  const Eigen::Vector3d dg = twist_at(dv.twist, s.g);
  // J = R Jbar R^T with dR = w~ R: dJ = w~ J - J w~ (text after Eq. 10), applied
  // to vectors only: dJ x = w x (J x) - J (w x x), no 3 x 3 products.
  const Eigen::Vector3d domega = dv.Z.tail<3>();
  const Eigen::Vector3d dalpha = dv.Zdot.tail<3>();
  const Eigen::Vector3d dgdot = dv.Z.head<3>() + domega.cross(s.g) + s.omega.cross(dg);  // Eq. (6)
  const Eigen::Vector3d dA = dv.Zdot.head<3>() + dalpha.cross(s.g) + s.alpha.cross(dg);
  const Eigen::Vector3d dF = s.m * (dA + domega.cross(s.gdot) + s.omega.cross(dgdot));
  const Eigen::Vector3d dJw = w.cross(s.Jw) - s.J * w.cross(s.omega) + s.J * domega;
  const Eigen::Vector3d dJa = w.cross(s.Ja) - s.J * w.cross(s.alpha);
  const Eigen::Vector3d dT = dJa + s.J * dalpha + domega.cross(s.Jw) + s.omega.cross(dJw);
  Vector6d dh;
  dh << dF, dg.cross(s.F) + s.g.cross(dF) + dT;
  return dh;
}

// vary_body_residual for a rate's variation: the geometry stands (twist 0),
// so every term of dg and of the turning of J drops out (the same sums less
// their exact zeros).
Vector6d vary_body_residual_rate(const BodyState& s, const Vector6d& dZ, const Vector6d& dZdot) {
  const Eigen::Vector3d domega = dZ.tail<3>();
  const Eigen::Vector3d dalpha = dZdot.tail<3>();
  const Eigen::Vector3d dgdot = dZ.head<3>() + domega.cross(s.g);  // Eq. (6)
  const Eigen::Vector3d dA = dZdot.head<3>() + dalpha.cross(s.g);
  const Eigen::Vector3d dF = s.m * (dA + domega.cross(s.gdot) + s.omega.cross(dgdot));
  const Eigen::Vector3d dJw = s.J * domega;
  const Eigen::Vector3d dT = s.J * dalpha + domega.cross(s.Jw) + s.omega.cross(dJw);
  Vector6d dh;
  dh << dF, s.g.cross(dF) + dT;
  return dh;
}

BodyState body_state(const Model& model, const Data& data, const DynamicsDerivativesWorkspace& ws,
                     int j) {
  const Body& body = model.bodies[j];
  BodyState s;
  s.m = body.mass;
  s.g = data.g_W[j];
  s.gdot = ws.gdot[j];
  s.omega = data.Z[j].tail<3>();
  s.alpha = ws.Zdot[j].tail<3>();
  s.J = ws.J[j];
  s.F = ws.h[j].head<3>();
  s.Jw = ws.Jw[j];
  s.Ja = ws.Ja[j];
  return s;
}

// The point's own force F_W: residual -= J_p^T F, and its derivatives in the
// point's motion.
void add_own_point_force(const Model& model, const Data& data, const PointForceTerm& f,
                         DynamicsDerivativesWorkspace& ws, Eigen::Ref<Eigen::MatrixXd>& K,
                         Eigen::Ref<Eigen::MatrixXd>& C) {
  const int e = f.point.body;
  const Eigen::Vector3d p = point_position(data, f.point);
  const Eigen::Vector3d omega = data.Z[e].tail<3>();
  for (int i = e; i != kGround; i = model.bodies[i].parent) {
    ws.cols.col(i) = twist_at(data.b[i], p);
    ws.residual[i] -= ws.cols.col(i).dot(f.F_W);
  }
  for (int k = e; k != kGround; k = model.bodies[k].parent) {
    // The point's motion per unit z_k: dp = col_k, dv from dZ_e = b_k x (Z_e - Z_k).
    const Eigen::Vector3d dp = ws.cols.col(k);
    const Vector6d dZ = motion_cross(data.b[k], Vector6d(data.Z[e] - data.Z[k]));
    const Eigen::Vector3d dv = twist_at(dZ, p) + omega.cross(dp);
    const Eigen::Vector3d dF = f.dF_dp * dp + f.dF_dv * dv;
    const Eigen::Vector3d dF_rate = f.dF_dv * dp;  // dv/dzd_k = col_k
    const Eigen::Vector3d wk = data.b[k].tail<3>();
    for (int i = e; i != kGround; i = model.bodies[i].parent) {
      // d col_i/dz_k: below k, col_i turns with the subtree (w_k x col_i); at or
      // above k, b_i is fixed and only p moves (w_i x dp).
      const Eigen::Vector3d dcol = i > k ? Eigen::Vector3d(wk.cross(ws.cols.col(i)))
                                         : Eigen::Vector3d(data.b[i].tail<3>().cross(dp));
      K(i, k) -= dcol.dot(f.F_W) + ws.cols.col(i).dot(dF);
      C(i, k) -= ws.cols.col(i).dot(dF_rate);
    }
  }
}

// Dependence of the point's force on the other point's motion (forces between
// two points): the columns J_p^T of the point's path, differentiated along the
// other point's path.
void add_other_point_force(const Model& model, const Data& data, const PointForceTerm& f,
                           DynamicsDerivativesWorkspace& ws, Eigen::Ref<Eigen::MatrixXd>& K,
                           Eigen::Ref<Eigen::MatrixXd>& C) {
  const int e = f.point.body;
  const int o = f.other.body;
  if (o == kGround) return;
  const Eigen::Vector3d p = point_position(data, f.point);
  for (int i = e; i != kGround; i = model.bodies[i].parent) ws.cols.col(i) = twist_at(data.b[i], p);
  const Eigen::Vector3d q = point_position(data, f.other);
  const Eigen::Vector3d omega_o = data.Z[o].tail<3>();
  for (int k = o; k != kGround; k = model.bodies[k].parent) {
    const Eigen::Vector3d dq = twist_at(data.b[k], q);
    const Vector6d dZ = motion_cross(data.b[k], Vector6d(data.Z[o] - data.Z[k]));
    const Eigen::Vector3d dw = twist_at(dZ, q) + omega_o.cross(dq);
    const Eigen::Vector3d dF = f.dF_dp_other * dq + f.dF_dv_other * dw;
    const Eigen::Vector3d dF_rate = f.dF_dv_other * dq;
    for (int i = e; i != kGround; i = model.bodies[i].parent) {
      K(i, k) -= ws.cols.col(i).dot(dF);
      C(i, k) -= ws.cols.col(i).dot(dF_rate);
    }
  }
}

// One point force's share: residual -= J_p^T F (the Q' of apply_point_force), and
// its derivatives. Column i of J_p is col_i = b_i at p for i on p's path (Eq. 4).
void add_point_force(const Model& model, const Data& data, const PointForceTerm& f,
                     DynamicsDerivativesWorkspace& ws, Eigen::Ref<Eigen::MatrixXd>& K,
                     Eigen::Ref<Eigen::MatrixXd>& C) {
  const int e = f.point.body;
  if (e == kGround) return;  // the ground takes it
  // A term carries the point's own force and its derivatives in its own
  // motion (the other point is the point itself), or the dependence on another
  // point's motion: the host fills one half and zeros the other. A zero half
  // would add exact zeros: skipped.
  const auto zero = [](const auto& a) { return (a.array() == 0.0).all(); };
  if (!zero(f.F_W) || !zero(f.dF_dp) || !zero(f.dF_dv))
    add_own_point_force(model, data, f, ws, K, C);
  if (!zero(f.dF_dp_other) || !zero(f.dF_dv_other)) add_other_point_force(model, data, f, ws, K, C);
}

// Entries (i, k) of K and C from the body terms,
// for i in k's subtree or above it (the others are left as they are), one
// subtree sweep of body variations per coordinate: the cheaper fill for shallow
// trees (see use_factored_fill). Only the
// subtree of coordinate k varies. For i in it, d(b_i . H_i) = (b_k x b_i) . H_i +
// b_i . dH_i (b_k itself is fixed on the parent; b_i does not depend on rates);
// for i above k, H_i contains the whole subtree: b_i . dH_k.
void fill_columns_by_subtree(const Model& model, const Data& data, DynamicsDerivativesWorkspace& ws,
                             Eigen::Ref<Eigen::MatrixXd>& K, Eigen::Ref<Eigen::MatrixXd>& C) {
  const int n = model.num_bodies();
  for (int k = 0; k < n; ++k) {
    const int* first = ws.subtree_bodies.data() + ws.subtree_start[k];
    const int* last = ws.subtree_bodies.data() + ws.subtree_start[k + 1];
    // K's and C's columns in one sweep: each body's state is gathered once.
    for (const int* it = first; it != last; ++it) {
      const int j = *it;
      const BodyState s = body_state(model, data, ws, j);
      ws.dH[j] = vary_body_residual(s, detail::variation_z(data, ws.Zdot, j, k));
      const BodyVariation dv = detail::variation_zd(data, j, k);
      ws.dH_rate[j] = vary_body_residual_rate(s, dv.Z, dv.Zdot);
    }
    for (const int* it = last - 1; it > first; --it) {
      const int p = model.bodies[*it].parent;
      ws.dH[p] += ws.dH[*it];
      ws.dH_rate[p] += ws.dH_rate[*it];
    }
    for (const int* it = first; it != last; ++it) {
      const int i = *it;
      double value = data.b[i].dot(ws.dH[i]);
      if (i != k) value += motion_cross(data.b[k], data.b[i]).dot(ws.H[i]);
      K(i, k) = value;
      C(i, k) = data.b[i].dot(ws.dH_rate[i]);
    }
    for (int i = model.bodies[k].parent; i != kGround; i = model.bodies[i].parent) {
      K(i, k) = data.b[i].dot(ws.dH[k]);
      C(i, k) = data.b[i].dot(ws.dH_rate[k]);
    }
  }
}

// 6 x 6 matrix of the motion cross product: cross_matrix(a) y = a x y, that is
// [[w~, v~], [0, w~]] for a = [v; w].
Matrix6d cross_matrix(const Vector6d& a) {
  const auto skew = [](const Eigen::Vector3d& x) {
    Eigen::Matrix3d S;
    S << 0.0, -x.z(), x.y(), x.z(), 0.0, -x.x(), -x.y(), x.x(), 0.0;
    return S;
  };
  Matrix6d X;
  X.topLeftCorner<3, 3>() = skew(a.tail<3>());
  X.topRightCorner<3, 3>() = skew(a.head<3>());
  X.bottomLeftCorner<3, 3>().setZero();
  X.bottomRightCorner<3, 3>() = X.topLeftCorner<3, 3>();
  return X;
}

// Body j's variation for coordinate k (ancestor of j or j), rewritten with the
// Jacobi identity so that it is linear in three vectors of k alone. With
// u_k = b_k x Z_k and c_k = -b_k x Zdot_k - Z_k x u_k, variation_z is
//   twist = b_k,  dZ = -Z_j x b_k - u_k,  dZdot = -Zdot_j x b_k + Z_j x u_k + c_k
// and variation_zd is twist = 0, dZ = b_k, dZdot = -Z_j x b_k - 2 u_k. The body
// residual's variation is linear in them: dh_j = A_j b_k - D_j u_k + C_j c_k (z)
// and D_j b_k - 2 C_j u_k (zd), with 6 x 6 matrices of body j alone (the u_k
// part of dZ, dZdot is minus the b_k part of the rate's, less the 2 u_k; C_j, the
// response to dZdot alone, is the body's Mbar of Eq. 9). Summed over subtrees and
// projected on b_i, every entry of K and C is then three 6-vector dot products,
// so the fill costs O(1) per (row, column) pair of the subtree.
void body_variation_matrices(const BodyState& s, const Vector6d& Zj, const Vector6d& Zdotj,
                             Matrix6d& A, Matrix6d& Cm, Matrix6d& D) {
  const Matrix6d XZ = cross_matrix(Zj);
  const Matrix6d XZdot = cross_matrix(Zdotj);
  for (int m = 0; m < 6; ++m) {
    const Vector6d e = Vector6d::Unit(m);
    BodyVariation dv;
    dv.twist = e;
    dv.Z = -XZ.col(m);
    dv.Zdot = -XZdot.col(m);
    A.col(m) = vary_body_residual(s, dv);
    dv.twist.setZero();
    dv.Z = e;
    dv.Zdot = -XZ.col(m);
    D.col(m) = vary_body_residual(s, dv);
  }
  // Eq. (9) about the world origin: [[m, -m g~], [m g~, J - m g~ g~]].
  const Matrix6d G = cross_matrix((Vector6d() << Eigen::Vector3d::Zero(), s.g).finished());
  const Eigen::Matrix3d g_skew = G.topLeftCorner<3, 3>();
  Cm.topLeftCorner<3, 3>() = s.m * Eigen::Matrix3d::Identity();
  Cm.topRightCorner<3, 3>() = -s.m * g_skew;
  Cm.bottomLeftCorner<3, 3>() = s.m * g_skew;
  Cm.bottomRightCorner<3, 3>() = s.J - s.m * g_skew * g_skew;
}

// K and C from the body terms, factored (for deep trees: see use_factored_fill).
// Only the subtree of coordinate k varies. For i
// in it, d(b_i . H_i) = (b_k x b_i) . H_i + b_i . dH_i (b_k itself is fixed on
// the parent; b_i does not depend on rates); for i above k, H_i contains the
// whole subtree: b_i . dH_k.
void fill_columns_factored(const Model& model, const Data& data, DynamicsDerivativesWorkspace& ws,
                           Eigen::Ref<Eigen::MatrixXd>& K, Eigen::Ref<Eigen::MatrixXd>& C) {
  const int n = model.num_bodies();
  for (int j = 0; j < n; ++j) {
    const BodyState s = body_state(model, data, ws, j);
    body_variation_matrices(s, data.Z[j], ws.Zdot[j], ws.SA[j], ws.SC[j], ws.SD[j]);
  }
  for (int j = n - 1; j >= 0; --j) {  // subtree sums
    const int p = model.bodies[j].parent;
    if (p == kGround) continue;
    ws.SA[p] += ws.SA[j];
    ws.SC[p] += ws.SC[j];
    ws.SD[p] += ws.SD[j];
  }
  for (int i = 0; i < n; ++i) {
    const Vector6d& bi = data.b[i];
    // (b_k x b_i) . H_i = b_k . (-(b_i x)^T H_i): zero for k = i.
    ws.row_b[i] = ws.SA[i].transpose() * bi - cross_matrix(bi).transpose() * ws.H[i];
    ws.row_c[i] = ws.SC[i].transpose() * bi;
    ws.row_rate_b[i] = ws.SD[i].transpose() * bi;
  }
  for (int k = 0; k < n; ++k) {
    const Vector6d& bk = data.b[k];
    const Vector6d u = motion_cross(bk, data.Z[k]);
    const Vector6d c = -motion_cross(bk, ws.Zdot[k]) - motion_cross(data.Z[k], u);
    for (int t = ws.subtree_start[k]; t < ws.subtree_start[k + 1]; ++t) {
      const int i = ws.subtree_bodies[static_cast<size_t>(t)];
      K(i, k) = ws.row_b[i].dot(bk) - ws.row_rate_b[i].dot(u) + ws.row_c[i].dot(c);
      C(i, k) = ws.row_rate_b[i].dot(bk) - 2.0 * ws.row_c[i].dot(u);
    }
    if (model.bodies[k].parent == kGround) continue;
    const Vector6d dH = ws.SA[k] * bk - ws.SD[k] * u + ws.SC[k] * c;
    const Vector6d dH_rate = ws.SD[k] * bk - 2.0 * (ws.SC[k] * u);
    for (int i = model.bodies[k].parent; i != kGround; i = model.bodies[i].parent) {
      K(i, k) = data.b[i].dot(dH);
      C(i, k) = data.b[i].dot(dH_rate);
    }
  }
}

// The last body on both paths to the ground (kGround when none): parents
// precede children, so the larger index steps up until the two meet.
int last_common_body(const Model& model, int a, int b) {
  while (a != b) {
    if (a > b)
      a = model.bodies[a].parent;
    else
      b = model.bodies[b].parent;
  }
  return a;
}

}  // namespace

DynamicsDerivativesWorkspace::DynamicsDerivativesWorkspace(const Model& model) {
  const auto nb = static_cast<std::size_t>(model.num_bodies());
  Zdot.assign(nb, Vector6d::Zero());
  h.assign(nb, Vector6d::Zero());
  H.assign(nb, Vector6d::Zero());
  dH.assign(nb, Vector6d::Zero());
  dH_rate.assign(nb, Vector6d::Zero());
  SA.assign(nb, Matrix6d::Zero());
  SC.assign(nb, Matrix6d::Zero());
  SD.assign(nb, Matrix6d::Zero());
  row_b.assign(nb, Vector6d::Zero());
  row_c.assign(nb, Vector6d::Zero());
  row_rate_b.assign(nb, Vector6d::Zero());
  J.assign(nb, Eigen::Matrix3d::Zero());
  gdot.assign(nb, Eigen::Vector3d::Zero());
  Jw.assign(nb, Eigen::Vector3d::Zero());
  Ja.assign(nb, Eigen::Vector3d::Zero());
  std::vector<std::vector<int>> below(nb);
  for (int j = 0; j < model.num_bodies(); ++j)
    for (int i = j; i != kGround; i = model.bodies[i].parent)
      below[static_cast<size_t>(i)].push_back(j);
  subtree_start.assign(nb + 1, 0);
  for (std::size_t k = 0; k < nb; ++k) {
    subtree_start[k + 1] = subtree_start[k] + static_cast<int>(below[k].size());
    subtree_bodies.insert(subtree_bodies.end(), below[k].begin(), below[k].end());
  }
  cols.setZero(3, model.num_coordinates());
  residual.setZero(model.num_coordinates());
  // The subtree sweep costs two body variations per (coordinate, descendant)
  // pair, i.e. 2 x (sum of depths); the factored fill about 12 per body plus a
  // few dot products per pair (measured on the bench's chains, CPU time: equal
  // near a mean depth of 6; chain of 8 bodies 17 us/step swept, 20 factored;
  // of 16, 56 swept, 45 factored).
  long depth_sum = 0;
  for (int j = 0; j < model.num_bodies(); ++j) {
    for (int i = j; i != kGround; i = model.bodies[i].parent) ++depth_sum;
  }
  use_factored_fill = depth_sum > 6L * model.num_bodies();
}

void dynamics_derivatives(const Model& model, const Data& data, const Eigen::VectorXd& zdd,
                          const std::vector<PointForceTerm>& forces,
                          DynamicsDerivativesWorkspace& ws, Eigen::Ref<Eigen::MatrixXd> K,
                          Eigen::Ref<Eigen::MatrixXd> C) {
  check_sizes(model, data, zdd, ws, K, C);
  const int n = model.num_bodies();

  // Nominal pass. Zdot_j = Zdot_parent + b_j zdd_j + d_j (Eq. 3), and the
  // body residuals h_j (Eqs. 9-10 with the weight as the applied load).
  for (int j = 0; j < n; ++j) {
    const Body& body = model.bodies[j];
    const int p = body.parent;
    const Vector6d Zdot_P = p == kGround ? Vector6d::Zero() : ws.Zdot[p];
    ws.Zdot[j] = Zdot_P + data.b[j] * zdd[j] + data.d[j];
    ws.J[j] = data.R_W_B[j] * body.inertia_B * data.R_W_B[j].transpose();
    ws.gdot[j] = twist_at(data.Z[j], data.g_W[j]);  // Eq. (6)
    ws.Jw[j] = ws.J[j] * data.Z[j].tail<3>();
    ws.Ja[j] = ws.J[j] * ws.Zdot[j].tail<3>();
    BodyState s = body_state(model, data, ws, j);
    ws.h[j] = body_residual(s, ws.Zdot[j], body.mass * model.gravity);
    ws.H[j] = ws.h[j];
  }
  for (int j = n - 1; j >= 0; --j) {  // T^T of Eq. (12): subtree sums
    const int p = model.bodies[j].parent;
    if (p != kGround) ws.H[p] += ws.H[j];
  }
  for (int i = 0; i < n; ++i) ws.residual[i] = data.b[i].dot(ws.H[i]);  // R_d^T, Eq. (12)

  // Every entry the fill leaves alone is zero: zeroed here, or kept zero by
  // the caller (zero_unrelated off). Entries of K and C are then set by the
  // fill (ancestor pairs) or accumulated by the forces between two points
  // (zeroed below, before the accumulation, where they are no ancestor pair).
  if (ws.zero_unrelated) {
    K.setZero();
    C.setZero();
  }
  if (ws.use_factored_fill) {
    fill_columns_factored(model, data, ws, K, C);
  } else {
    fill_columns_by_subtree(model, data, ws, K, C);
  }
  if (!ws.zero_unrelated) {
    for (const PointForceTerm& f : forces) {
      if (f.point.body == kGround || f.other.body == kGround) continue;
      // The pairs of bodies on the two paths to the ground where neither is
      // the other's ancestor: both below the paths' last common body (one
      // on both paths lies on one root path with every body of either, so
      // its pairs are ancestor pairs, the fill's).
      const int common = last_common_body(model, f.point.body, f.other.body);
      for (int k = f.other.body; k != common; k = model.bodies[k].parent)
        for (int i = f.point.body; i != common; i = model.bodies[i].parent) {
          K(i, k) = 0.0;
          C(i, k) = 0.0;
        }
    }
  }
  for (const PointForceTerm& f : forces) add_point_force(model, data, f, ws, K, C);
}

}  // namespace mh
