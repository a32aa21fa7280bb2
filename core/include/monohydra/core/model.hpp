// The fixed description of a multibody system: bodies in a tree of relative
// joints, named body points and cut joints. A Model never changes during a run;
// everything that does lives in Data (data.hpp). Units are SI throughout.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace mh {

enum class JointType { revolute, prismatic };

// Index used for "the ground" wherever a body index is expected.
inline constexpr int kGround = -1;

// One body and the joint that connects it to its parent (Sect. 2.1).
//
// Frames: body j has a frame B_j whose origin is the joint point. With P the
// parent's frame (the world frame for the ground) and z_j the joint coordinate:
//   revolute:  R_W_Bj = R_W_P * Rot(axis_P, z_j) * R_P_B0,  o_Bj = o_P + R_W_P * joint_P
//   prismatic: R_W_Bj = R_W_P * R_P_B0,                     o_Bj = o_P + R_W_P * (joint_P + axis_P
//   z_j)
// so z_j is a relative angle (rad) or a relative length (m).
struct Body {
  std::string name;
  std::string coordinate;  // name of z_j in results, e.g. "z1" (position in the model file)
  int parent = kGround;    // parents always precede their children in Model::bodies
  JointType joint = JointType::revolute;
  Eigen::Vector3d joint_P = Eigen::Vector3d::Zero();     // joint point, parent frame
  Eigen::Vector3d axis_P = Eigen::Vector3d::UnitZ();     // unit joint axis, parent frame
  Eigen::Matrix3d R_P_B0 = Eigen::Matrix3d::Identity();  // body orientation at z = 0
  double mass = 0.0;                                     // kg
  Eigen::Vector3d com_B = Eigen::Vector3d::Zero();       // centre of mass, body frame
  Eigen::Matrix3d inertia_B = Eigen::Matrix3d::Zero();   // about the COM, body frame (kg m^2)
  double z0 = 0.0;                                       // initial coordinate
  double zd0 = 0.0;                                      // initial rate
};

// A point fixed on a body (or on the ground), given in that body's frame.
struct BodyPoint {
  int body = kGround;
  Eigen::Vector3d p_B = Eigen::Vector3d::Zero();
};

enum class CutJointType { revolute, spherical, translational };

// A joint that closes a kinematic loop (Sect. 2.2): it is not part of the tree
// but imposes constraints Phi(z) = 0 between a point of body a and one of body b.
// Rows (constraints.hpp): revolute 3 + 2, spherical 3, translational 2 + 3 in
// 3D; in a planar model revolute and spherical 2, translational 2.
struct CutJoint {
  std::string name;
  CutJointType type = CutJointType::revolute;
  BodyPoint a;
  BodyPoint b;
  Eigen::Vector3d axis_a = Eigen::Vector3d::UnitZ();  // joint axis in body a's frame
  Eigen::Vector3d axis_b = Eigen::Vector3d::UnitZ();  // the same axis in body b's frame
};

struct Model {
  std::string name;
  std::vector<Body> bodies;  // topological order: parent index < own index
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, -9.81, 0.0);  // m/s^2, world frame
  std::vector<CutJoint> cut_joints;
  // A planar model moves in the XY plane: revolute axes are Z, and cut joints
  // impose only their in-plane constraints (the paper's case studies).
  bool planar = false;
  // Bodies whose coordinates the initial assembly of the loops keeps as given.
  std::vector<int> assembly_fixed;

  int num_bodies() const { return static_cast<int>(bodies.size()); }
  // Number of relative joint coordinates (one per body: every joint has 1 DOF).
  int num_coordinates() const { return static_cast<int>(bodies.size()); }
  Eigen::VectorXd initial_coordinates() const;
  Eigen::VectorXd initial_rates() const;
};

}  // namespace mh
