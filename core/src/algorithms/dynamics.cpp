// Open-loop semirecursive dynamics (Sect. 2.1, Eqs. 8-12).
#include "monohydra/core/dynamics.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace mh {
namespace {

bool is_body(const Data& data, int body) {
  return body >= 0 && body < static_cast<int>(data.f_W.size());
}

void check_load_body(const char* where, const Data& data, int body) {
  if (body != kGround && !is_body(data, body)) {
    throw std::invalid_argument(std::string(where) + ": body: expected " + std::to_string(kGround) +
                                ".." + std::to_string(static_cast<int>(data.f_W.size()) - 1) +
                                ", got " + std::to_string(body));
  }
}

void check_data(const char* where, const Model& model, const Data& data) {
  if (static_cast<int>(data.R_W_B.size()) != model.num_bodies() ||
      data.M.rows() != model.num_coordinates()) {
    throw std::invalid_argument(std::string(where) + ": data (bodies): expected " +
                                std::to_string(model.num_bodies()) + ", got " +
                                std::to_string(data.R_W_B.size()));
  }
}

// Inertia tensor about the COM in world axes, J_j = A_j Jbar_j A_j^T (text after Eq. 10).
Eigen::Matrix3d world_inertia(const Body& body, const Eigen::Matrix3d& R_W_B) {
  return R_W_B * body.inertia_B * R_W_B.transpose();
}

// Eq. (9): Mbar_j = D_j^T M_j D_j = [m I, -m g~; m g~, J - m g~ g~], kept as
// (m, c = m g, I_O = J - m g~ g~), with -g~ g~ = |g|^2 I - g g^T.
Eigen::Matrix3d origin_inertia(const Eigen::Matrix3d& J, const Eigen::Vector3d& c,
                               const Eigen::Vector3d& g) {
  Eigen::Matrix3d I_O = J - c * g.transpose();
  I_O.diagonal().array() += c.dot(g);
  return I_O;
}

}  // namespace

void reset_applied_forces(const Model& model, Data& data) {
  check_data("reset_applied_forces", model, data);
  for (int j = 0; j < model.num_bodies(); ++j) {
    data.f_W[j] = model.bodies[j].mass * model.gravity;  // weight acts at the COM: no moment
    data.tau_W[j].setZero();
  }
}

void apply_point_force(Data& data, int body, const Eigen::Vector3d& p_W,
                       const Eigen::Vector3d& F_W) {
  check_load_body("apply_point_force", data, body);
  if (body == kGround) return;
  data.f_W[body] += F_W;
  // Moments are kept about the COM (Eq. 10): transport the force from p to g.
  data.tau_W[body] += (p_W - data.g_W[body]).cross(F_W);
}

void apply_body_moment(Data& data, int body, const Eigen::Vector3d& tau_W) {
  check_load_body("apply_body_moment", data, body);
  if (body == kGround) return;
  data.tau_W[body] += tau_W;
}

namespace {

// Body j's Mbar_j (Eq. 9) as (m, c, I_O) in data.m_sum, c_sum, I_sum and its
// Qbar_j - Mbar_j Zdot0_j (Eqs. 10, 11) in data.Q_sum: its own terms, before
// any subtree sum.
void body_terms(const Model& model, Data& data, int j) {
  const Body& body = model.bodies[j];
  const double m = body.mass;
  const Eigen::Vector3d& g = data.g_W[j];
  const Eigen::Matrix3d J = world_inertia(body, data.R_W_B[j]);
  const Eigen::Vector3d sdot = data.Z[j].head<3>();
  const Eigen::Vector3d omega = data.Z[j].tail<3>();
  const Eigen::Vector3d gdot = sdot + omega.cross(g);  // Eq. (6)

  const Eigen::Vector3d c = m * g;
  const Eigen::Matrix3d I_O = origin_inertia(J, c, g);  // Eq. (9)

  // Eq. (10): Qbar_j = D_j^T (Q_j - M_j e_j). Zdot here is the plain time
  // derivative of Z (Eq. 5, d_j = bdot_j zd_j), and then Eq. (7)'s velocity
  // term is e_j = Ddot_j Z_j = [omega x gdot; 0]. Eq. (10) as printed has
  // omega x (omega x g) in its place; the two differ by omega x sdot, which is
  // not zero in general (e.g. a pendulum whose axis misses the world origin).
  const Eigen::Vector3d f_net = data.f_W[j] - m * omega.cross(gdot);
  const Eigen::Vector3d tau = data.tau_W[j] - omega.cross(J * omega) + g.cross(f_net);

  // Eq. (11): Qbar - Mbar T Rdot_d zd, per body, with Mbar [a; alpha] =
  // [m a - c x alpha; c x a + I_O alpha].
  const Eigen::Vector3d a0 = data.Zdot0[j].head<3>();
  const Eigen::Vector3d alpha0 = data.Zdot0[j].tail<3>();
  Vector6d& Qs = data.Q_sum[j];
  Qs.head<3>() = f_net - (m * a0 - c.cross(alpha0));
  Qs.tail<3>() = tau - (c.cross(a0) + I_O * alpha0);
  data.m_sum[j] = m;
  data.c_sum[j] = c;
  data.I_sum[j] = I_O;
}

}  // namespace

Matrix6d body_mass_matrix(const Model& model, const Data& data, int j) {
  const Body& body = model.bodies[j];
  const Eigen::Vector3d& g = data.g_W[j];
  const Eigen::Vector3d c = body.mass * g;
  Eigen::Matrix3d c_x;
  c_x << 0.0, -c.z(), c.y(), c.z(), 0.0, -c.x(), -c.y(), c.x(), 0.0;
  Matrix6d M;
  M.topLeftCorner<3, 3>() = body.mass * Eigen::Matrix3d::Identity();
  M.topRightCorner<3, 3>() = -c_x;
  M.bottomLeftCorner<3, 3>() = c_x;
  M.bottomRightCorner<3, 3>() = origin_inertia(world_inertia(body, data.R_W_B[j]), c, g);
  return M;
}

void mass_matrix_and_forces(const Model& model, Data& data) {
  check_data("mass_matrix_and_forces", model, data);
  const int n = model.num_bodies();
  for (int j = 0; j < n; ++j) body_terms(model, data, j);

  // T^T (...) of Eq. (12): accumulate each body's terms into all its ancestors.
  // Children follow their parents, so a backward sweep finishes every subtree
  // before it is added to its parent.
  for (int j = n - 1; j >= 0; --j) {
    const int p = model.bodies[j].parent;
    if (p == kGround) continue;
    data.m_sum[p] += data.m_sum[j];
    data.c_sum[p] += data.c_sum[j];
    data.I_sum[p] += data.I_sum[j];
    data.Q_sum[p] += data.Q_sum[j];
  }

  // Eq. (12): (T^T Mbar T)_{ik} = sum of Mbar_j over bodies j below both i and k,
  // which for i an ancestor of k (or k itself) is the composite of k; zero when
  // neither is an ancestor of the other. Those entries keep the zero Data was
  // made with (this loop writes the ancestor pairs only, the same ones every
  // call), so M is not cleared: that cost n^2 a call, 43 % of a step of a
  // 257-body tree of bounded depth.
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d bv = data.b[k].head<3>();
    const Eigen::Vector3d bw = data.b[k].tail<3>();
    const Eigen::Vector3d& c = data.c_sum[k];
    Vector6d Mb_k;
    Mb_k << data.m_sum[k] * bv - c.cross(bw), c.cross(bv) + data.I_sum[k] * bw;
    for (int i = k; i != kGround; i = model.bodies[i].parent) {
      const double value = data.b[i].dot(Mb_k);
      data.M(i, k) = value;
      data.M(k, i) = value;
    }
    data.Q[k] = data.b[k].dot(data.Q_sum[k]);  // Eq. (12)
  }
}

void inverse_dynamics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& zdd,
                      Eigen::Ref<Eigen::VectorXd> r) {
  check_data("inverse_dynamics", model, data);
  const int n = model.num_bodies();
  if (zdd.size() != n || r.size() != n)
    throw std::invalid_argument("inverse_dynamics: zdd and r: expected " + std::to_string(n) +
                                " entries, got " + std::to_string(zdd.size()) + " and " +
                                std::to_string(r.size()));
  for (int j = 0; j < n; ++j) {
    body_terms(model, data, j);
    // The part of Zdot_j that zdd makes, T R_d zdd (Eq. 5 less Zdot0), and
    // Mbar_j of it less the body's Qbar - Mbar Zdot0: its share of Eq. (12).
    const int p = model.bodies[j].parent;
    data.A_zdd[j] = data.b[j] * zdd[j];
    if (p != kGround) data.A_zdd[j] += data.A_zdd[p];
    const Eigen::Vector3d a = data.A_zdd[j].head<3>();
    const Eigen::Vector3d alpha = data.A_zdd[j].tail<3>();
    const Eigen::Vector3d& c = data.c_sum[j];
    Vector6d& h = data.Q_sum[j];
    h.head<3>() = data.m_sum[j] * a - c.cross(alpha) - h.head<3>();
    h.tail<3>() = c.cross(a) + data.I_sum[j] * alpha - h.tail<3>();
  }
  // R_d^T T^T of Eq. (12): subtree sums, then each joint's projection.
  for (int j = n - 1; j >= 0; --j) {
    const int p = model.bodies[j].parent;
    if (p != kGround) data.Q_sum[p] += data.Q_sum[j];
  }
  for (int j = 0; j < n; ++j) r[j] = data.b[j].dot(data.Q_sum[j]);
}

double kinetic_energy(const Model& model, const Data& data) {
  check_data("kinetic_energy", model, data);
  double T = 0.0;
  for (int j = 0; j < model.num_bodies(); ++j) {
    const Body& body = model.bodies[j];
    const Eigen::Vector3d omega = data.Z[j].tail<3>();
    const Eigen::Vector3d gdot = data.Z[j].head<3>() + omega.cross(data.g_W[j]);  // Eq. (6)
    const Eigen::Matrix3d J = world_inertia(body, data.R_W_B[j]);
    T += 0.5 * (body.mass * gdot.squaredNorm() + omega.dot(J * omega));
  }
  return T;
}

double potential_energy(const Model& model, const Data& data) {
  check_data("potential_energy", model, data);
  double V = 0.0;
  for (int j = 0; j < model.num_bodies(); ++j) {
    V -= model.bodies[j].mass * model.gravity.dot(data.g_W[j]);
  }
  return V;
}

}  // namespace mh
