// colosim bench peer (bench_peer.h): the scope in colosim and in MuJoCo, side by side.
#include "bench/bench_peer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/timing.h"
#include "collision/contact_query.h"
#include "core/numbers.h"
#include "core/scope_step.h"
#include "trainer/assets.h"

#ifdef COLOSIM_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace colosim {

bool peerAvailable() {
#ifdef COLOSIM_HAVE_MUJOCO
  return true;
#else
  return false;
#endif
}

BenchOutput benchPeerDefault() { return benchPeer(PeerOptions{}); }

#ifndef COLOSIM_HAVE_MUJOCO

BenchOutput benchPeer(const PeerOptions&) {
  BenchOutput out;
  out.exit_code = 2;
  out.error =
      "MuJoCo is not installed: this build of colosim has no MuJoCo to compare with "
      "(install Debian's libmujoco-dev, e.g. by scripts/setup, then configure and build again)";
  out.json = {{"benchmark", "peer"}, {"error", out.error}};
  out.text = out.error + "\n";
  return out;
}

#else

namespace {

// The script, the same for both: the tip from 0.30 m to 0.45 m through the rectum and
// sigmoid at 1.5 cm/s (a brisk clinical advance), its speed ramped up over the first
// second, while the handle turns +-0.6 rad back and forth (period 5 s, starting at rest).
constexpr double kStartInsertion_m = 0.30;
constexpr double kInsertionSpeed_m_per_s = 0.015;
constexpr double kRamp_s = 1.0;
constexpr double kRotationAmplitude_rad = 0.6;
constexpr double kRotationPeriod_s = 5.0;

struct HandleScript {
  double insertion_m, rotation_rad, insertion_rate_m_per_s, rotation_rate_rad_per_s;
};

HandleScript scriptAt(double t_s) {
  HandleScript h;
  const double v = kInsertionSpeed_m_per_s;
  if (t_s < kRamp_s) {
    h.insertion_m = kStartInsertion_m + 0.5 * v * t_s * t_s / kRamp_s;
    h.insertion_rate_m_per_s = v * t_s / kRamp_s;
  } else {
    h.insertion_m = kStartInsertion_m + v * (t_s - 0.5 * kRamp_s);
    h.insertion_rate_m_per_s = v;
  }
  const double w = 2 * kPi / kRotationPeriod_s;
  h.rotation_rad = kRotationAmplitude_rad * std::sin(w * t_s) * std::sin(0.5 * w * t_s);
  h.rotation_rate_rad_per_s = kRotationAmplitude_rad * w *
                              (std::cos(w * t_s) * std::sin(0.5 * w * t_s) +
                               0.5 * std::sin(w * t_s) * std::cos(0.5 * w * t_s));
  return h;
}

// MuJoCo's tube: rings of kTubeSides capsules parallel to the centreline, their inner
// crests at the lumen radius, one ring per kTubePiece_m of centreline, each ring a static
// body (the broadphase culls whole rings). Capsules of radius kWallCapsuleRadius times
// the lumen radius overlap their neighbours (between two, the wall lies 11 % further out
// than at the crests) and close the outside of bends with their caps. Capsules are
// MuJoCo's cheapest geoms: rings of 12 boxes of 2 cm walls cost 1.8 ms of collision per
// step against 0.8 ms (4 mm walls let the scope through at the sigmoid), with the tip as
// close to colosim's; rings every 15 mm instead of 7.5 mm saved 10 % and moved the tip
// rms difference from 7 to 10 mm.
constexpr int kTubeSides = 12;
constexpr double kTubePiece_m = 0.0075;
constexpr double kWallCapsuleRadius = 0.6;
// The guide outside the anus holding the part of the chain not yet inserted straight
// (colosim's kinematic outside part): frictionless, 0.5 mm of clearance at the crests.
constexpr int kGuideSides = 12;
constexpr double kGuidePiece_m = 0.02;
constexpr double kGuideClearance_m = 0.0005;
// Handle servos (proportional-derivative, critically damped on the handle's armature
// plus the chain): insertion kp [N/m], rotation kp [N m/rad]. The armatures stand for
// the hand and handle; their inertial forces are tiny at the script's accelerations.
constexpr double kSlideKp_N_per_m = 1e5, kSlideArmature_kg = 0.5;
constexpr double kHingeKp_Nm_per_rad = 100, kHingeArmature_kgm2 = 1e-3;
// Rotor inertia of each elastic hinge [kg m^2]: MuJoCo integrates joint stiffness
// explicitly, and the segments' own inertia (8.6e-8 across, 5.9e-8 about the axis) against
// EI / h = 2 and GJ / h = 27 N m/rad puts the chain's fastest modes far beyond 2 / dt; the
// chain threaded in the colon shook itself out of the tube in 0.1 s. 2e-6 is the smallest
// of 2e-7, 5e-7, 1e-6, 2e-6 that settled quietly (MuJoCo's usual remedy, "armature").
constexpr double kElasticArmature_kgm2 = 2e-6;
// Contact softness: MuJoCo's stiffest safe time constant at 1 ms (2 dt), critically damped.
constexpr double kContactTimeconst_s = 0.002;

std::string fmt(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", x);
  return b;
}

std::string vec(const Vec3& v) { return fmt(v.x()) + " " + fmt(v.y()) + " " + fmt(v.z()); }

// A unit quaternion (w x y z) of a rotation matrix.
std::string quat(const Mat3& R) {
  const Eigen::Quaterniond q(R);
  return fmt(q.w()) + " " + fmt(q.x()) + " " + fmt(q.y()) + " " + fmt(q.z());
}

// A frame whose z axis is `axis` (unit).
Mat3 frameAlong(const Vec3& axis) {
  Mat3 R;
  const Vec3 x = axis.unitOrthogonal();
  R.col(0) = x;
  R.col(1) = axis.cross(x);
  R.col(2) = axis;
  return R;
}

// One ring of `sides` capsules parallel to the axis of a static body at `centre` with
// frame R (z along the tube), their inner crests at radius r, overlapping their
// neighbours; half length half_len (plus the caps).
void addRing(std::ostringstream& xml, const Vec3& centre, const Mat3& R, double r, double half_len, int sides,
             const char* cls) {
  xml << "<body pos=\"" << vec(centre) << "\" quat=\"" << quat(R) << "\">";
  const double rc = kWallCapsuleRadius * r;
  for (int j = 0; j < sides; ++j) {
    const double a = 2 * kPi * j / sides;
    const Vec3 p = (r + rc) * Vec3(std::cos(a), std::sin(a), 0);
    xml << "<geom class=\"" << cls << "\" type=\"capsule\" size=\"" << fmt(rc) << "\" fromto=\""
        << vec(p - half_len * Vec3::UnitZ()) << " " << vec(p + half_len * Vec3::UnitZ()) << "\"/>";
  }
  xml << "</body>\n";
}

// Intrinsic x-y-z angles (a, b, c) with R = Rx(a) Ry(b) Rz(c): MuJoCo composes a body's
// hinges in the order they are declared, each about its axis in the turned frame.
Vec3 xyzAngles(const Mat3& R) {
  const double b = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  return Vec3(std::atan2(-R(1, 2), R(2, 2)), b, std::atan2(-R(0, 1), R(0, 0)));
}

struct MjDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
  void operator()(mjData* d) const { mj_deleteData(d); }
};

struct Peer {
  std::unique_ptr<mjModel, MjDeleter> model;
  std::unique_ptr<mjData, MjDeleter> data;
  int chain = 0;       // bodies of the chain, proximal (the handle, 0) to tip (chain - 1)
  int first_body = 0;  // MuJoCo body id of chain body 0
  int tube_geoms = 0;
};

// The MJCF of the scope chain threaded as colosim's state `s` (segment k of colosim is
// chain body chain - 1 - k), the tube along the frozen colon, and the guide.
std::string peerXml(const WorldModel& m, const WorldState& s, int chain, double tube_reach_m, double guide_length_m,
                    double dt_s, int* tube_geoms) {
  const ScopeModel& sm = m.scope;
  const double h = sm.h_m, r = sm.radius_m;
  const Vec3 e = sm.R_W_entry.col(2);
  std::ostringstream xml;
  xml << "<mujoco model=\"colosim_peer\">\n"
      << "<compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
      << "<option timestep=\"" << fmt(dt_s) << "\" gravity=\"" << vec(sm.gravity_m_per_s2)
      << "\" integrator=\"implicit\"/>\n"
      << "<size njmax=\"4000\" nconmax=\"1000\"/>\n"
      << "<default>\n"
      // Scope geoms collide with the walls only (contype 1 & conaffinity 0 among themselves).
      << "<default class=\"scope\"><geom contype=\"1\" conaffinity=\"0\" condim=\"3\" friction=\"0 0 0\"/></default>\n"
      << "<default class=\"wall\"><geom contype=\"0\" conaffinity=\"1\" condim=\"3\" friction=\""
      << fmt(m.contact.friction_coefficient) << " 0 0\" solref=\"" << fmt(kContactTimeconst_s) << " 1\"/></default>\n"
      << "<default class=\"guide\"><geom contype=\"0\" conaffinity=\"1\" condim=\"1\" solref=\""
      << fmt(kContactTimeconst_s) << " 1\"/></default>\n"
      << "</default>\n<worldbody>\n";

  // The colon tube along the frozen centreline, from the anus to tube_reach_m of rest arclength.
  const ColonModel& c = m.colon;
  const Points& q = s.colon.q;
  int geoms = 0;
  std::vector<Vec3> pts;
  std::vector<double> rad;
  for (int j = 0; j + 1 < c.n; ++j) {
    const int per = std::max(1, static_cast<int>(std::ceil(c.segment_length_m(j) / kTubePiece_m)));
    for (int k = 0; k < per; ++k) {
      const double p = static_cast<double>(k) / per;
      if (c.arclengthAt(j, p) > tube_reach_m) break;
      pts.push_back(splinePoint(q, j, p));
      rad.push_back(c.radiusAt(j, p));
    }
    if (c.arclengthAt(j, 1.0) > tube_reach_m) break;
  }
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const Vec3 d = pts[i + 1] - pts[i];
    const double len = d.norm();
    const Vec3 axis = d / len;
    // Overlap with the neighbours: the outside of a bend by angle a opens by about r a
    // (the caps add kWallCapsuleRadius r more).
    double bend = 0;
    if (i + 2 < pts.size()) bend = std::acos(std::clamp(axis.dot((pts[i + 2] - pts[i + 1]).normalized()), -1.0, 1.0));
    if (i > 0) bend = std::max(bend, std::acos(std::clamp(axis.dot((pts[i] - pts[i - 1]).normalized()), -1.0, 1.0)));
    const double radius = 0.5 * (rad[i] + rad[i + 1]);
    addRing(xml, 0.5 * (pts[i] + pts[i + 1]), frameAlong(axis), radius, 0.5 * len + radius * bend,
            kTubeSides, "wall");
    geoms += kTubeSides;
  }
  // The guide outside the anus, along -e.
  const Mat3 Rg = frameAlong(e);
  for (double x = 0; x < guide_length_m; x += kGuidePiece_m) {
    addRing(xml, sm.p_W_anus - (x + 0.5 * kGuidePiece_m) * e, Rg, r + kGuideClearance_m, 0.5 * kGuidePiece_m + 0.001,
            kGuideSides, "guide");
    geoms += kGuideSides;
  }
  *tube_geoms = geoms;

  // The chain: body 0 is the handle end (colosim segment chain - 1), straight along the
  // entry axis, on a slide (insertion, qpos = the insertion depth) and a hinge (rotation)
  // about it; each further body hangs h beyond its parent's origin on three hinges.
  const double beta = sm.params.joint_damping_s;
  const Vec3& I = sm.segment_inertia_kgm2;
  auto segmentBody = [&](int i) {
    xml << "<inertial pos=\"0 0 " << fmt(0.5 * h) << "\" mass=\"" << fmt(sm.segment_mass_kg) << "\" diaginertia=\""
        << vec(I) << "\"/>"
        << "<geom class=\"scope\" type=\"capsule\" size=\"" << fmt(r) << "\" fromto=\"0 0 0 0 0 " << fmt(h) << "\"/>";
    if (i == chain - 1) xml << "<site name=\"tip\" pos=\"0 0 " << fmt(h) << "\"/>";
    xml << "\n";
  };
  const Vec3 p0 = sm.p_W_anus - chain * h * e;  // body 0's proximal end at insertion 0
  xml << "<body name=\"seg0\" pos=\"" << vec(p0) << "\" quat=\"" << quat(sm.R_W_entry) << "\">"
      << "<joint name=\"insertion\" type=\"slide\" axis=\"0 0 1\" armature=\"" << fmt(kSlideArmature_kg) << "\"/>"
      << "<joint name=\"rotation\" type=\"hinge\" axis=\"0 0 1\" armature=\"" << fmt(kHingeArmature_kgm2) << "\"/>";
  segmentBody(0);
  for (int i = 1; i < chain; ++i) {
    xml << "<body name=\"seg" << i << "\" pos=\"0 0 " << fmt(h) << "\">";
    const char* axes[3] = {"1 0 0", "0 1 0", "0 0 1"};
    // Body i joins body i - 1 as colosim's joint between segments chain - 1 - i and chain - i.
    const Vec3& kj = sm.joint_stiffness_Nm_per_rad[chain - 1 - i];
    for (int a = 0; a < 3; ++a)
      xml << "<joint type=\"hinge\" axis=\"" << axes[a] << "\" armature=\"" << fmt(kElasticArmature_kgm2)
          << "\" stiffness=\"" << fmt(kj[a]) << "\" damping=\""
          << fmt(beta * kj[a]) << "\"/>";
    segmentBody(i);
  }
  for (int i = 0; i < chain; ++i) xml << "</body>";
  xml << "\n</worldbody>\n<actuator>\n";
  // force = kp (ctrl - q) - kv qdot; ctrl carries the rate as ctrl = q* + (kv / kp) qdot*.
  const double m_slide = kSlideArmature_kg + chain * sm.segment_mass_kg;
  const double kv_slide = 2 * std::sqrt(kSlideKp_N_per_m * m_slide);
  const double kv_hinge = 2 * std::sqrt(kHingeKp_Nm_per_rad * kHingeArmature_kgm2);
  xml << "<general name=\"push\" joint=\"insertion\" biastype=\"affine\" gainprm=\"" << fmt(kSlideKp_N_per_m) << "\" biasprm=\"0 "
      << fmt(-kSlideKp_N_per_m) << " " << fmt(-kv_slide) << "\"/>\n"
      << "<general name=\"turn\" joint=\"rotation\" biastype=\"affine\" gainprm=\"" << fmt(kHingeKp_Nm_per_rad) << "\" biasprm=\"0 "
      << fmt(-kHingeKp_Nm_per_rad) << " " << fmt(-kv_hinge) << "\"/>\n"
      << "</actuator>\n</mujoco>\n";
  return xml.str();
}

// MuJoCo's default error handler waits for a key press; a benchmark must not.
void mujocoError(const char* msg) {
  std::fprintf(stderr, "colosim bench peer: MuJoCo error: %s\n", msg);
  std::exit(1);
}

// MuJoCo's warnings (e.g. too many contacts) are counted and reported, not written to
// MUJOCO_LOG.TXT in the working directory.
int mujoco_warnings = 0;
void mujocoWarning(const char*) { ++mujoco_warnings; }

Peer makePeer(const WorldModel& m, const WorldState& s, int chain, double tube_reach_m, double guide_length_m,
              double dt_s) {
  mju_user_error = mujocoError;
  mju_user_warning = mujocoWarning;
  mujoco_warnings = 0;
  Peer p;
  p.chain = chain;
  const std::string xml = peerXml(m, s, chain, tube_reach_m, guide_length_m, dt_s, &p.tube_geoms);
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), "peer.xml", static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("bench peer: MuJoCo's virtual file system refused the model");
  const int f = mj_findFileVFS(vfs.get(), "peer.xml");
  std::memcpy(vfs->filedata[f], xml.data(), xml.size());
  char err[1000] = "";
  p.model.reset(mj_loadXML("peer.xml", vfs.get(), err, sizeof err));
  mj_deleteVFS(vfs.get());
  if (!p.model) throw std::runtime_error(std::string("bench peer: MuJoCo did not load the model: ") + err);
  p.data.reset(mj_makeData(p.model.get()));
  p.first_body = mj_name2id(p.model.get(), mjOBJ_BODY, "seg0");

  // The threaded pose: chain body i is colosim's segment k = chain - 1 - i.
  mjData* d = p.data.get();
  const mjModel* mm = p.model.get();
  d->qpos[0] = s.scope.input.insertion_m;
  d->qpos[1] = s.scope.input.rotation_rad;
  for (int i = 1; i < chain; ++i) {
    const int k = chain - 1 - i;
    const Vec3 a = xyzAngles(s.scope.R_WS[k + 1].transpose() * s.scope.R_WS[k]);
    const int jnt = mm->body_jntadr[p.first_body + i];
    for (int c = 0; c < 3; ++c) d->qpos[mm->jnt_qposadr[jnt + c]] = a[c];
  }
  mj_forward(p.model.get(), d);
  return p;
}

Vec3 peerTip(const Peer& p) {
  const int site = 0;
  const double* x = p.data->site_xpos + 3 * site;
  return Vec3(x[0], x[1], x[2]);
}

}  // namespace

BenchOutput benchPeer(const PeerOptions& o) {
  if (!(o.duration_s > 0) || !(o.dt_s > 0) || o.block_steps < 1)
    throw std::invalid_argument("bench peer: duration, time step and block size must be positive");
  const Parameters params = loadParameters(assetPath("params/default.json"));
  const WorldModel m = loadWorldModel(assetPath("anatomy/adult.json"), params);
  WorldState s = makeWorldState(m);
  threadScopeAlongColon(m, s, kStartInsertion_m, 0.0);
  const int steps = std::max(1, static_cast<int>(std::lround(o.duration_s / o.dt_s)));
  const double end_insertion_m = scriptAt(steps * o.dt_s).insertion_m;

  // MuJoCo: a chain long enough for the deepest insertion plus two segments outside,
  // the tube as far as the tip can reach (the bends take it a little deeper) and the
  // guide as long as the chain outside at the start.
  const int chain = static_cast<int>(std::ceil(end_insertion_m / m.scope.h_m)) + 2;
  if (chain > m.scope.segment_count) throw std::invalid_argument("bench peer: the script inserts beyond the scope");
  Peer peer = makePeer(m, s, chain, end_insertion_m + 0.1, chain * m.scope.h_m - kStartInsertion_m + 0.02, o.dt_s);
  mjModel* mm = peer.model.get();
  mjData* md = peer.data.get();
  const int push = mj_name2id(mm, mjOBJ_ACTUATOR, "push"), turn = mj_name2id(mm, mjOBJ_ACTUATOR, "turn");
  const double kv_over_kp_slide = -mm->actuator_biasprm[push * mjNBIAS + 2] / mm->actuator_gainprm[push * mjNGAIN];
  const double kv_over_kp_hinge = -mm->actuator_biasprm[turn * mjNBIAS + 2] / mm->actuator_gainprm[turn * mjNGAIN];
  const double drag_Ns_per_m = m.scope.params.drag_Ns_per_m2 * m.scope.h_m;

  FclContactQuery query(m);
  std::vector<double> colosim_block_us, mujoco_block_us, colosim_block_cpu_us, mujoco_block_cpu_us;
  double tip_sq = 0, force_sq = 0, colosim_force_sq = 0, mujoco_force_sq = 0, tip_max = 0;
  long colosim_contacts = 0, mujoco_contacts = 0;
  Vec3 colosim_tip = tipPosition(m.scope, s.scope), mujoco_tip = peerTip(peer);
  const double start_tip_difference_m = (colosim_tip - mujoco_tip).norm();
  std::vector<Vec3> colosim_tips(steps), mujoco_tips(steps);
  std::vector<double> colosim_force(steps), mujoco_force(steps);
  using Clock = std::chrono::steady_clock;
  for (int first = 0; first < steps; first += o.block_steps) {
    const int last = std::min(steps, first + o.block_steps);
    // colosim, colon frozen: contacts and their forces on the scope, then the scope step.
    double c0 = threadCpuSeconds();
    auto t0 = Clock::now();
    for (int n = first; n < last; ++n) {
      const HandleScript hs = scriptAt((n + 1) * o.dt_s);
      HandleInput in;
      in.insertion_m = hs.insertion_m;
      in.rotation_rad = hs.rotation_rad;
      query.findWallContacts(m, s);
      s.colon.loads.clear();
      s.scope.loads.clear();
      applyWallContacts(m.contact, m.colon, s.colon, m.scope, s.scope, s.wall, s.colon.loads, s.scope.loads,
                        &s.contact_limit);
      stepScope(m.scope, s.scope, in, o.dt_s);
      colosim_tips[n] = tipPosition(m.scope, s.scope);
      colosim_force[n] = s.scope.handle.force_N;
      colosim_contacts += static_cast<long>(s.wall.size());
    }
    auto t1 = Clock::now();
    double c1 = threadCpuSeconds();
    colosim_block_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / (last - first));
    colosim_block_cpu_us.push_back(1e6 * (c1 - c0) / (last - first));
    // MuJoCo: the handle servos' targets, the drag, one mj_step.
    c0 = threadCpuSeconds();
    t0 = Clock::now();
    for (int n = first; n < last; ++n) {
      const HandleScript hs = scriptAt((n + 1) * o.dt_s);
      md->ctrl[push] = hs.insertion_m + kv_over_kp_slide * hs.insertion_rate_m_per_s;
      md->ctrl[turn] = hs.rotation_rad + kv_over_kp_hinge * hs.rotation_rate_rad_per_s;
      for (int i = 0; i < chain; ++i) {
        const int b = peer.first_body + i;
        mjtNum v[6];
        mj_objectVelocity(mm, md, mjOBJ_XBODY, b, v, 0);  // (angular, linear) at the body's origin, world
        // Linear velocity of the centre of mass: v + w x (xipos - xpos).
        const Vec3 w(v[0], v[1], v[2]);
        const Vec3 arm(md->xipos[3 * b] - md->xpos[3 * b], md->xipos[3 * b + 1] - md->xpos[3 * b + 1],
                       md->xipos[3 * b + 2] - md->xpos[3 * b + 2]);
        const Vec3 vc = Vec3(v[3], v[4], v[5]) + w.cross(arm);
        for (int a = 0; a < 3; ++a) md->xfrc_applied[6 * b + a] = -drag_Ns_per_m * vc[a];
      }
      mj_step(mm, md);
      // mj_step leaves the kinematics of the step's start: the tip before step n, which
      // is colosim's after step n - 1.
      if (n > 0) mujoco_tips[n - 1] = peerTip(peer);
      mujoco_force[n] = md->actuator_force[push];
      mujoco_contacts += md->ncon;
    }
    t1 = Clock::now();
    c1 = threadCpuSeconds();
    mujoco_block_us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count() / (last - first));
    mujoco_block_cpu_us.push_back(1e6 * (c1 - c0) / (last - first));
  }
  mj_kinematics(mm, md);
  mujoco_tips[steps - 1] = peerTip(peer);
  for (int n = 0; n < steps; ++n) {
    const double dx = (colosim_tips[n] - mujoco_tips[n]).norm();
    tip_sq += dx * dx;
    tip_max = std::max(tip_max, dx);
    const double df = colosim_force[n] - mujoco_force[n];
    force_sq += df * df;
    colosim_force_sq += colosim_force[n] * colosim_force[n];
    mujoco_force_sq += mujoco_force[n] * mujoco_force[n];
  }
  colosim_tip = colosim_tips.back();
  mujoco_tip = mujoco_tips.back();
  const bool finite = colosim_tip.allFinite() && mujoco_tip.allFinite();
  if (!finite) throw std::runtime_error("bench peer: a simulation diverged (non-finite tip)");

  const double colosim_us = median(colosim_block_us), mujoco_us = median(mujoco_block_us);
  const double colosim_cpu = median(colosim_block_cpu_us), mujoco_cpu = median(mujoco_block_cpu_us);
  const double tip_rms = std::sqrt(tip_sq / steps), force_rms = std::sqrt(force_sq / steps);
  const double colosim_force_rms = std::sqrt(colosim_force_sq / steps);
  const double mujoco_force_rms = std::sqrt(mujoco_force_sq / steps);
  const double colosim_depth = (colosim_tip - m.scope.p_W_anus).norm();
  BenchOutput out;
  out.json = {{"benchmark", "peer"},
              {"mujoco_version", mj_version()},
              {"duration_s", steps * o.dt_s},
              {"dt_s", o.dt_s},
              {"steps", steps},
              {"block_steps", o.block_steps},
              {"colosim_step_us", colosim_us},
              {"mujoco_step_us", mujoco_us},
              {"speed_ratio", mujoco_us / colosim_us},
              {"tip_rms_difference_m", tip_rms},
              {"tip_max_difference_m", tip_max},
              {"tip_start_difference_m", start_tip_difference_m},
              {"tip_final_difference_m", (colosim_tip - mujoco_tip).norm()},
              {"colosim_tip_final_m", {colosim_tip.x(), colosim_tip.y(), colosim_tip.z()}},
              {"mujoco_tip_final_m", {mujoco_tip.x(), mujoco_tip.y(), mujoco_tip.z()}},
              {"handle_force_rms_difference_N", force_rms},
              {"colosim_handle_force_rms_N", colosim_force_rms},
              {"mujoco_handle_force_rms_N", mujoco_force_rms},
              {"colosim_handle_force_final_N", colosim_force.back()},
              {"mujoco_handle_force_final_N", mujoco_force.back()},
              {"colosim_wall_contacts_mean", static_cast<double>(colosim_contacts) / steps},
              {"mujoco_contacts_mean", static_cast<double>(mujoco_contacts) / steps},
              {"colosim_segments_inside_final", s.scope.inside},
              {"mujoco_chain_bodies", chain},
              {"mujoco_dofs", mm->nv},
              {"mujoco_tube_geoms", peer.tube_geoms},
              {"mujoco_warnings", mujoco_warnings},
              {"cpu", {{"colosim_step_us", colosim_cpu}, {"mujoco_step_us", mujoco_cpu},
                       {"speed_ratio", mujoco_cpu / colosim_cpu}}}};
  char buf[1400];
  std::snprintf(
      buf, sizeof buf,
      "peer: the scope in colosim and in MuJoCo %d.%d.%d, colon rigid in both, %.1f s of scripted insertion\n"
      "(%.2f -> %.3f m) and rotation (+-%.1f rad) at dt = %.0f ms; medians of blocks of %d steps:\n"
      "                          wall time   thread CPU time\n"
      "  colosim step          %9.1f us %12.1f us  (%d segments inside at the end, %.1f wall contacts on average)\n"
      "  MuJoCo step           %9.1f us %12.1f us  (%d bodies, %d dofs, %d tube geoms, %.1f contacts on average)\n"
      "  speed ratio MuJoCo / colosim %6.2f x %11.2f x\n"
      "  tip position difference: rms %.1f mm, largest %.1f mm, at the start %.2f mm, at the end %.1f mm\n"
      "  handle force: rms colosim %.2f N, MuJoCo %.2f N, rms of the difference %.2f N\n"
      "  (colosim's tip %.3f m from the anus in a straight line at the end)\n",
      mj_version() / 100, mj_version() / 10 % 10, mj_version() % 10, steps * o.dt_s, kStartInsertion_m,
      end_insertion_m, kRotationAmplitude_rad, o.dt_s * 1e3, o.block_steps, colosim_us, colosim_cpu, s.scope.inside,
      static_cast<double>(colosim_contacts) / steps, mujoco_us, mujoco_cpu, chain, mm->nv, peer.tube_geoms,
      static_cast<double>(mujoco_contacts) / steps, mujoco_us / colosim_us, mujoco_cpu / colosim_cpu, 1e3 * tip_rms,
      1e3 * tip_max, 1e3 * start_tip_difference_m, 1e3 * (colosim_tip - mujoco_tip).norm(), colosim_force_rms,
      mujoco_force_rms, force_rms, colosim_depth);
  out.text = buf;
  return out;
}

#endif  // COLOSIM_HAVE_MUJOCO

}  // namespace colosim
