// The report folder of `colosim identify RECORDING --report DIR` for a recorded insertion:
// PNG plots made by gnuplot (pngcairo, as the tension report in identify/tension/report.h) of
// the measured handle force and torque against the paper's model and the extended model,
// over time and against insertion depth with push and pull apart, the residuals, the
// diagnosis and the JSON result.
#pragma once

#include <string>

#include "identify/insertion/identify.h"

namespace colosim {

/// Writes dir/ (created if missing):
///   force_time.png      handle force [N] and torque [N m] over time: measured, paper, extended
///   force_depth.png     force and torque against insertion depth [m], push and pull apart,
///                       one column per model
///   residuals.png       force residual (measured - model) [N] against depth, push / pull,
///                       and over time, both models
///   insertion.dat, report.gp (the data and gnuplot script behind the plots), diagnosis.txt,
///   identify.json.
/// The predictions include each model's fitted sensor offsets. Throws std::runtime_error when
/// a file cannot be written or gnuplot fails.
void writeOrganReport(const std::string& dir, const InsertionRecording& rec, const InsertionIdentifyResult& r);

}  // namespace colosim
