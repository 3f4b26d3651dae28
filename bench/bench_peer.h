// colosim bench peer: colosim's scope against the same scope in MuJoCo (Debian's
// libmujoco-dev 2.2.2), in one process, with the colon held rigid in both (issue 18).
//
// The same work on both sides:
//  - the scope: segment length h, mass and inertia per segment, the elastic joints' EI / h
//    about d1 and d2 and GJ / h about d3 (MuJoCo: three hinges per joint, stiffness and
//    damping beta K as colosim's joints), gravity, viscous drag, friction coefficient mu;
//  - threaded in the same colon centreline (threadScopeAlongColon), colon frozen:
//    colosim's colon is not stepped (contacts, their forces on the scope, the scope step);
//    MuJoCo's colon is a rigid tube of box rings along the same centreline and radius,
//    as far as the scope can reach;
//  - the same scripted insertion and rotation of the handle, at dt = 1 ms.
// What differs (MuJoCo has no kinematic outside part and no per-point penalty wall): the
// MuJoCo chain starts outside the anus in a straight frictionless guide tube and is
// driven at its proximal end by stiff position servos (the handle); its contacts are
// MuJoCo's soft constraints (solref below), not colosim's 1000 N/m per interaction point.
#pragma once

#include "bench/registry.h"

namespace colosim {

struct PeerOptions {
  double duration_s = 10.0;  ///< simulated time of the script [s]
  double dt_s = 1e-3;        ///< time step of both simulations [s]
  int block_steps = 100;     ///< steps per timed block (medians are over blocks)
};

/// Whether this build has MuJoCo (found by CMake at configure time).
bool peerAvailable();

/// The side-by-side run. Without MuJoCo: exit_code 2 and an error saying so.
BenchOutput benchPeer(const PeerOptions& options = {});

}  // namespace colosim
