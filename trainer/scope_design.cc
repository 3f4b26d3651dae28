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
  const std::string format = top.string("format");
  if (format != "colosim-scope") top.fail("format", "expected 'colosim-scope', got '" + format + "'");
  const int version = top.integer("version", 0, 1000000);
  if (version != 1) top.fail("version", "unsupported version " + std::to_string(version) + " (this build reads 1)");

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
  const nlohmann::json& sections = profile.raw("sections");
  if (!sections.is_array() || sections.empty() || sections.size() > 1000)
    profile.fail("sections", "expected a list of 1 to 1000 sections from the tip");
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
  d.tip_light_reach_m = top.quantity("tip_light_reach", "m", 0.001, 0.2);
  d.sheath_friction = top.quantity("sheath_friction", "1", 0.0, 2.0);
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
  params.tip_light_reach_m = design.tip_light_reach_m;
}

}  // namespace colosim
