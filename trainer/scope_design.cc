#include "trainer/scope_design.h"

#include <cmath>

#include "trainer/assets.h"
#include "trainer/json_position.h"
#include "trainer/strict_json.h"

namespace colosim {

ScopeDesign loadScopeDesign(const std::string& path) { return parseScopeDesign(readTextFile(path), path); }

namespace {

ScopeDesign designFromJson(const std::string& text, const std::string& file) {
  const nlohmann::json j = parseJsonText(text, file);
  JsonObject top(j, file);
  top.formatAndVersion("colosim-scope");

  ScopeDesign d;
  d.file = file;
  d.hash = hashBytes(text);
  d.name = top.string("name");
  if (d.name.empty()) top.fail("name", "must not be empty");
  d.description = top.string("description");
  d.working_length_m = top.quantity("working_length", "m", 0.1, 3.0);
  d.outer_diameter_m = top.quantity("outer_diameter", "m", 0.002, 0.03);
  d.mass_per_length_kg_per_m = top.quantity("mass_per_length", "kg/m", 0.01, 5.0);

  JsonObject profile = top.object("stiffness_profile");
  const nlohmann::json& sections = profile.list("sections", 1, 1000, "sections from the tip");
  for (size_t i = 0; i < sections.size(); ++i) {
    JsonObject s(sections[i], file, profile.keyPath("sections[" + std::to_string(i) + "]"));
    StiffnessSection sec;
    const double from_m = d.stiffness_profile.empty() ? 0.0 : d.stiffness_profile.back().to_m;
    sec.to_m = s.number("to_m", 0.0, 3.0);
    if (!(sec.to_m > from_m))
      s.fail("to_m", "must be beyond the previous section's end (" + std::to_string(from_m) + " m from the tip)");
    sec.bending_stiffness_Nm2 = s.number("bending_stiffness_Nm2", 1e-4, 10.0);
    sec.torsional_stiffness_Nm2 = s.number("torsional_stiffness_Nm2", 1e-4, 100.0);
    s.ignore("note");
    s.finish();
    d.stiffness_profile.push_back(sec);
  }
  if (std::abs(d.stiffness_profile.back().to_m - d.working_length_m) > 1e-9)
    profile.fail("sections", "the last section must end at the working length (" +
                                 std::to_string(d.working_length_m) + " m)");
  profile.ignore("source");
  profile.ignore("note");
  profile.finish();

  d.bending_section_length_m = top.quantity("bending_section_length", "m", 0.01, 0.3);
  if (!(d.bending_section_length_m < d.working_length_m))
    top.fail("bending_section_length", "must be shorter than the working length");
  d.knob_updown_max_rad = top.quantity("knob_updown_max", "rad", 0.0, kKnobUpDownMax_rad);
  d.knob_leftright_max_rad = top.quantity("knob_leftright_max", "rad", 0.0, kKnobLeftRightMax_rad);
  if (top.has("knob_moment_limit")) d.knob_moment_limit_Nm = top.quantity("knob_moment_limit", "N m", 0.0, 10.0);
  d.tip_light_reach_m = top.quantity("tip_light_reach", "m", 0.001, 0.2);
  d.sheath_friction = top.quantity("sheath_friction", "1", 0.0, 2.0);
  if (top.has("active")) {
    // An active scope (issue 20): its joints from the tip over actuated_length_m bent by actuators.
    JsonObject a = top.object("active");
    d.active.enabled = true;
    const std::string strategy = a.choice("strategy", {"follow_the_leader", "contact_minimising"});
    d.active.strategy =
        strategy == "follow_the_leader" ? ActiveStrategy::kFollowTheLeader : ActiveStrategy::kContactMinimising;
    d.active.joint_torque_limit_Nm = a.number("joint_torque_limit_Nm", 1e-4, 100.0);
    d.active.time_constant_s = a.number("time_constant_s", 1e-3, 100.0);
    d.active.actuated_length_m = a.number("actuated_length_m", 0.0, 3.0);
    if (!(d.active.actuated_length_m <= d.working_length_m))
      a.fail("actuated_length_m", "must be within the working length (" + std::to_string(d.working_length_m) + " m)");
    if (a.has("contact_gain")) d.active.contact_gain = a.number("contact_gain", 0.0, 1000.0);
    if (a.has("contact_relax_s")) d.active.contact_relax_s = a.number("contact_relax_s", 1e-3, 1e4);
    a.ignore("source");
    a.ignore("note");
    a.finish();
  }
  if (top.has("variable_stiffness")) {
    // A section whose EI the operator switches between levels (multipliers of the profile's EI).
    JsonObject v = top.object("variable_stiffness");
    VariableStiffnessParams& vs = d.variable_stiffness;
    vs.from_m = v.number("from_m", 0.0, 3.0);
    vs.to_m = v.number("to_m", 0.0, 3.0);
    if (!(vs.to_m > vs.from_m)) v.fail("to_m", "must be beyond from_m");
    if (!(vs.to_m <= d.working_length_m + 1e-9))
      v.fail("to_m", "must be within the working length (" + std::to_string(d.working_length_m) + " m)");
    const nlohmann::json& levels = v.list("levels", 2, kStiffnessLevelsMax, "EI multipliers");
    for (size_t i = 0; i < levels.size(); ++i) {
      if (!levels[i].is_number()) v.fail("levels", "level " + std::to_string(i) + " is not a number");
      const double x = levels[i].get<double>();
      if (!(x >= 0.01 && x <= 100.0))
        v.fail("levels", "level " + std::to_string(i) + " is " + std::to_string(x) + ", expected 0.01 to 100 (an EI multiplier)");
      vs.levels.push_back(x);
    }
    vs.default_level = v.integer("default_level", 0, static_cast<int>(vs.levels.size()) - 1);
    v.ignore("source");
    v.ignore("note");
    v.finish();
  }
  top.ignore("note");
  top.finish();
  return d;
}

}  // namespace

ScopeDesign parseScopeDesign(const std::string& text, const std::string& file) {
  try {
    return designFromJson(text, file);
  } catch (const InputError& e) {
    throw InputError(addLineToMessage(e.what(), file, text));
  }
}

void applyScopeDesign(const ScopeDesign& design, ScopeParams& params) {
  params.working_length_m = design.working_length_m;
  params.outer_diameter_m = design.outer_diameter_m;
  params.mass_per_length_kg_per_m = design.mass_per_length_kg_per_m;
  params.stiffness_profile = design.stiffness_profile;
  // The uniform values stand for the design's first (distal) section where one number is
  // needed (the model's checks); the joints take the profile.
  params.bending_stiffness_Nm2 = design.stiffness_profile.front().bending_stiffness_Nm2;
  params.torsional_stiffness_Nm2 = design.stiffness_profile.front().torsional_stiffness_Nm2;
  params.bending_section_length_m = design.bending_section_length_m;
  params.knob_updown_max_rad = design.knob_updown_max_rad;
  params.knob_leftright_max_rad = design.knob_leftright_max_rad;
  params.knob_moment_limit_Nm = design.knob_moment_limit_Nm;
  params.tip_light_reach_m = design.tip_light_reach_m;
  params.active = design.active;
  params.variable_stiffness = design.variable_stiffness;
}

}  // namespace colosim
