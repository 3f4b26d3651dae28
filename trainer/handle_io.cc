#include "trainer/handle_io.h"

namespace colosim {

HandleInput readHandleInput(JsonObject& obj) {
  HandleInput in;
  in.insertion_m = obj.number("insertion_m", 0.0, kInsertionMax_m);
  in.rotation_rad = obj.number("rotation_rad", -kRotationMax_rad, kRotationMax_rad);
  in.knob_updown_rad = obj.number("knob_updown_rad", -kKnobUpDownMax_rad, kKnobUpDownMax_rad);
  in.knob_leftright_rad = obj.number("knob_leftright_rad", -kKnobLeftRightMax_rad, kKnobLeftRightMax_rad);
  if (obj.has("stiffness_level")) in.stiffness_level = obj.integer("stiffness_level", 0, kStiffnessLevelsMax - 1);
  return in;
}

void writeHandleInput(nlohmann::json& obj, const HandleInput& in) {
  obj["insertion_m"] = in.insertion_m;
  obj["rotation_rad"] = in.rotation_rad;
  obj["knob_updown_rad"] = in.knob_updown_rad;
  obj["knob_leftright_rad"] = in.knob_leftright_rad;
  if (in.stiffness_level >= 0) obj["stiffness_level"] = in.stiffness_level;
}

bool sameInput(const HandleInput& a, const HandleInput& b) {
  return a.insertion_m == b.insertion_m && a.rotation_rad == b.rotation_rad &&
         a.knob_updown_rad == b.knob_updown_rad && a.knob_leftright_rad == b.knob_leftright_rad &&
         a.stiffness_level == b.stiffness_level;
}

}  // namespace colosim
