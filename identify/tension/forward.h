// The forward model of a tension test: the colon's own tension law driven by the
// imposed elongation history, through the same evaluate()/advance() calls, in the same
// order, as the colon step (core/colon_step.cc). One implementation, not two.
#pragma once

#include <vector>

#include "identify/tension/tension_test.h"
#include "core/tension_law.h"

namespace colosim {

/// Strain e_k = elongation_k / L [-] and strain rate by backward differences
/// (e_k - e_{k-1}) / (t_k - t_{k-1}) [1/s] (0 at k = 0): the velocity a backward-Euler
/// colon step holds at the start of step k when it moved through the same positions.
void tensionStrainHistory(const TensionTest& test, std::vector<double>* strain,
                          std::vector<double>* strain_rate);

/// Force of the law along the strain history [N]: at each sample k, F_k = evaluate(e_k,
/// edot_k, dt_k, z), then advance(e_{k+1}, edot_{k+1}, dt_{k+1}, z), with z initialised by
/// initInternal (a virgin sample at k = 0). dt_k = t_{k+1} - t_k (the last one repeats).
void simulateLawForce(const TensionLaw& law, const std::vector<double>& time_s,
                      const std::vector<double>& strain, const std::vector<double>& strain_rate,
                      std::vector<double>* force_N);

/// What the bench measures: offset + max(0, F). A sample held in grips cannot push, so it
/// goes slack (zero force) whenever the law would give compression [N].
void benchForce(const TensionLaw& law, double offset_N, const std::vector<double>& time_s,
                const std::vector<double>& strain, const std::vector<double>& strain_rate,
                std::vector<double>* measured_N);

}  // namespace colosim
