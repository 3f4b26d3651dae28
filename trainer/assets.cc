#include "trainer/assets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "trainer/strict_json.h"
#include "trainer/tension_law_file.h"

#ifndef COLOSIM_ASSET_DIR
#define COLOSIM_ASSET_DIR "assets"
#endif

namespace colosim {

std::string assetDir() {
  if (const char* env = std::getenv("COLOSIM_ASSETS"); env && *env) return env;
  return COLOSIM_ASSET_DIR;
}

std::string assetPath(const std::string& relative) { return assetDir() + "/" + relative; }

namespace {
constexpr uint64_t kFnvOffset = 14695981039346656037ull;
constexpr uint64_t kFnvPrime = 1099511628211ull;
}  // namespace

uint64_t hashFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return 0;
  uint64_t h = kFnvOffset;
  char c;
  while (in.get(c)) {
    h ^= static_cast<unsigned char>(c);
    h *= kFnvPrime;
  }
  return h;
}

uint64_t hashBytes(const std::string& bytes) {
  uint64_t h = kFnvOffset;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= kFnvPrime;
  }
  return h;
}

namespace {

void checkHeader(JsonObject& top, const std::string& format) {
  top.formatAndVersion(format);
  top.ignore("description");
}

}  // namespace

Parameters loadParameters(const std::string& path) { return parseParameters(readTextFile(path), path); }

Parameters parseParameters(const std::string& text, const std::string& path) {
  const nlohmann::json j = parseJsonText(text, path);
  JsonObject top(j, path);
  checkHeader(top, "colosim-params");
  Parameters p;
  p.file = path;
  p.hash = hashBytes(text);

  JsonObject colon = top.object("colon");
  ColonParams& c = p.colon;
  c.mass_per_length_kg_per_m = colon.quantity("mass_per_length", "kg/m", 1e-3, 10.0);
  const double k_density = colon.quantity("tension_stiffness_density", "N/m/m", 1.0, 1e6);
  const double ref_len = colon.quantity("tension_reference_length", "m", 1e-3, 10.0);
  // The paper's stiffness per unit length of sample, times the sample length squared:
  // EA = k_density * L^2 (assets/params/default.json explains the reading).
  c.tension_EA_N = k_density * ref_len * ref_len;
  c.tension_EC_Ns = colon.quantity("tension_viscosity", "N s", 0.0, 1e3);
  c.control_point_spacing_m = colon.quantity("control_point_spacing", "m", 0.002, 0.1);
  // Extensions of issue 7 (core/colon_extensions.h); 0 is the paper's model.
  c.bending_EI_Nm2 = colon.quantity("bending_rigidity", "N m^2", 0.0, 10.0);
  c.mesentery_stiffening_per_m2 = colon.quantity("mesentery_stiffening", "1/m^2", 0.0, 1e6);
  // Optional (files written before it: the paper's element, 1).
  if (colon.has("compression_stiffness_fraction"))
    c.compression_stiffness_fraction = colon.quantity("compression_stiffness_fraction", "1", 1e-3, 1.0);
  // Optional (files written before it: the paper's isotropic lifters, 1).
  if (colon.has("mesentery_axial_ratio"))
    c.mesentery_axial_ratio = colon.quantity("mesentery_axial_ratio", "1", 0.0, 1.0);
  // Optional (files written before it: the paper's smooth tube, 0).
  if (colon.has("haustral_fold_depth"))
    c.haustral_fold_depth = colon.quantity("haustral_fold_depth", "1", 0.0, 0.9);
  if (colon.has("haustral_fold_period"))
    c.haustral_fold_period_m = colon.quantity("haustral_fold_period", "m", 0.005, 1.0);
  // An identified tension law (optional; trainer/tension_law_file.h): its EA and EC must be
  // the ones above, so that the file states one axial stiffness.
  if (colon.has("tension_law")) {
    JsonObject law = colon.object("tension_law");
    p.tension_law = readTensionLawObject(law);
    auto same = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); };
    char msg[256];
    if (!same(p.tension_law->ea_N, c.tension_EA_N)) {
      std::snprintf(msg, sizeof msg, "%.9g N differs from the EA of the parameter set, tension_stiffness_density x "
                    "tension_reference_length^2 = %.9g N", p.tension_law->ea_N, c.tension_EA_N);
      law.fail("params.EA_N", msg);
    }
    if (!same(p.tension_law->ec_Ns, c.tension_EC_Ns)) {
      std::snprintf(msg, sizeof msg, "%.9g N s differs from tension_viscosity = %.9g N s", p.tension_law->ec_Ns,
                    c.tension_EC_Ns);
      law.fail("params.EC_Ns", msg);
    }
  }
  colon.finish();

  JsonObject mes = top.object("mesentery");
  for (const std::string& name : mes.keys()) {
    JsonObject cls = mes.object(name);
    MesenteryClass mc;
    mc.stiffness_N_per_m2 = cls.quantity("stiffness", "N/m/m", 0.0, 1e7);
    mc.damping_Ns_per_m2 = cls.quantity("damping", "N s/m/m", 0.0, 1e5);
    cls.finish();
    c.mesentery[name] = mc;
  }
  if (c.mesentery.empty()) mes.fail("", "at least one mesentery class is required");
  mes.finish();

  JsonObject scope = top.object("scope");
  ScopeParams& sp = p.scope;
  sp.working_length_m = scope.quantity("working_length", "m", 0.1, 3.0);
  sp.outer_diameter_m = scope.quantity("outer_diameter", "m", 0.002, 0.03);
  sp.mass_per_length_kg_per_m = scope.quantity("mass_per_length", "kg/m", 0.01, 5.0);
  sp.bending_stiffness_Nm2 = scope.quantity("bending_stiffness", "N m^2", 1e-4, 10.0);
  sp.torsional_stiffness_Nm2 = scope.quantity("torsional_stiffness", "N m^2/rad", 1e-4, 100.0);
  sp.bending_section_length_m = scope.quantity("bending_section_length", "m", 0.01, 0.3);
  sp.segment_length_m = scope.quantity("segment_length", "m", 0.002, 0.05);
  sp.joint_stiffness_N_per_m = scope.quantity("joint_stiffness", "N/m", 1e3, 1e9);
  sp.joint_damping_s = scope.quantity("joint_damping", "s", 0.0, 1.0);
  sp.drag_Ns_per_m2 = scope.quantity("drag", "N s/m/m", 0.0, 1e3);
  sp.slices_per_segment = static_cast<int>(scope.quantity("slices_per_segment", "1", 1, 8));
  sp.points_per_slice = static_cast<int>(scope.quantity("points_per_slice", "1", 1, 32));
  if (sp.slices_per_segment != scope.raw("slices_per_segment")["value"].get<double>() ||
      sp.points_per_slice != scope.raw("points_per_slice")["value"].get<double>())
    scope.fail("points_per_slice", "slice and point counts must be whole numbers");
  scope.finish();

  JsonObject contact = top.object("contact");
  ContactParams& cp = p.contact;
  cp.wall_stiffness_N_per_m = contact.quantity("wall_stiffness", "N/m", 0.0, 1e6);
  cp.wall_damping_Ns_per_m = contact.quantity("wall_damping", "N s/m", 0.0, 1e4);
  if (contact.has("wall_reference_slice_length"))
    cp.wall_reference_slice_m = contact.quantity("wall_reference_slice_length", "m", 0.0, 0.1);
  if (contact.has("wall_reference_points_per_slice")) {
    const double n = contact.quantity("wall_reference_points_per_slice", "1", 0.0, 32.0);
    if (n != static_cast<int>(n)) contact.fail("wall_reference_points_per_slice", "must be a whole number");
    cp.wall_reference_points_per_slice = static_cast<int>(n);
  }
  if (contact.has("wall_thickness")) cp.wall_thickness_m = contact.quantity("wall_thickness", "m", 0.0, 0.02);
  if (contact.has("wall_backing_stiffness"))
    cp.wall_backing_stiffness_N_per_m = contact.quantity("wall_backing_stiffness", "N/m", 0.0, 1e6);
  if (contact.has("threading_stiffness"))
    cp.threading_stiffness_N_per_m = contact.quantity("threading_stiffness", "N/m", 0.0, 1e6);
  if (contact.has("sphincter_stiffness"))
    p.scope.sphincter_stiffness_N_per_m = contact.quantity("sphincter_stiffness", "N/m", 1.0, 1e8);
  cp.friction_coefficient = contact.quantity("friction_coefficient", "1", 0.0, 2.0);
  cp.friction_velocity_m_per_s = contact.quantity("friction_velocity", "m/s", 1e-6, 1.0);
  cp.self_stiffness_N_per_m = contact.quantity("self_stiffness", "N/m", 0.0, 1e6);
  cp.self_damping_Ns_per_m = contact.quantity("self_damping", "N s/m", 0.0, 1e4);
  cp.self_neighbour_radii = contact.quantity("self_neighbour_radii", "1", 0.0, 100.0);
  cp.query_margin_m = contact.quantity("query_margin", "m", 0.0, 0.2);
  if (contact.has("coupling_predictor")) {
    const double on = contact.quantity("coupling_predictor", "1", 0.0, 1.0);
    if (on != 0 && on != 1) contact.fail("coupling_predictor", "must be 0 or 1");
    cp.coupling_predictor = on == 1;
  }
  if (contact.has("coupling_sweeps")) {
    const double n = contact.quantity("coupling_sweeps", "1", 0.0, 8.0);
    if (n != static_cast<int>(n)) contact.fail("coupling_sweeps", "must be a whole number");
    cp.coupling_sweeps = static_cast<int>(n);
  }
  contact.finish();

  JsonObject env = top.object("environment");
  c.gravity_m_per_s2 = env.quantity("gravity", "m/s^2", 0.0, 100.0);
  c.patient_position = env.quantityChoice("patient_position", {"left_lateral", "right_lateral", "supine", "prone"});
  env.finish();

  top.finish();
  return p;
}

Anatomy loadAnatomy(const std::string& path) { return parseAnatomy(readTextFile(path), path); }

Anatomy parseAnatomy(const std::string& text, const std::string& path) {
  const nlohmann::json j = parseJsonText(text, path);
  JsonObject top(j, path);
  checkHeader(top, "colosim-anatomy");
  Anatomy a;
  a.name = top.string("name");
  top.ignore("frame");
  const nlohmann::json& regions = top.raw("regions");
  if (!regions.is_array() || regions.empty()) top.fail("regions", "expected a non-empty list of regions");
  size_t total_points = 0;
  for (size_t i = 0; i < regions.size(); ++i) {
    JsonObject r(regions[i], path, "regions[" + std::to_string(i) + "]");
    AnatomyRegion reg;
    reg.name = r.string("name");
    if (reg.name.empty()) r.fail("name", "must not be empty");
    reg.mesentery = r.string("mesentery");
    // A lumen radius outside 2 mm .. 10 cm is a wrong unit or a typo.
    const std::vector<double> radius = r.numbers("radius_m", 0.002, 0.1, 2, 2);
    reg.radius_start_m = radius[0];
    reg.radius_end_m = radius[1];
    const nlohmann::json& pts = r.raw("points_m");
    if (!pts.is_array() || pts.empty()) r.fail("points_m", "expected a non-empty list of [x, y, z] points");
    for (size_t k = 0; k < pts.size(); ++k) {
      const std::string key = "points_m[" + std::to_string(k) + "]";
      if (!pts[k].is_array() || pts[k].size() != 3) r.fail(key, "expected [x, y, z] in metres");
      Vec3 p;
      for (int d = 0; d < 3; ++d) {
        if (!pts[k][d].is_number() || !std::isfinite(pts[k][d].get<double>()))
          r.fail(key, "coordinates must be finite numbers");
        p(d) = pts[k][d].get<double>();
        // A body is well under 2 m across: larger coordinates are a wrong unit.
        if (std::abs(p(d)) > 2.0) r.fail(key, "coordinate out of range [-2, 2] m (wrong unit?)");
      }
      reg.points_m.push_back(p);
    }
    total_points += reg.points_m.size();
    r.ignore("note");
    r.finish();
    a.regions.push_back(std::move(reg));
  }
  if (total_points < 2) top.fail("regions", "at least two waypoints are required");
  top.finish();
  return a;
}

}  // namespace colosim

namespace colosim {
ColonModel loadColonModel(const std::string& anatomy_path, const Parameters& params,
                          std::shared_ptr<const TensionLaw> law) {
  return colonModelOf(loadAnatomy(anatomy_path), anatomy_path, params, std::move(law));
}

ColonModel colonModelOf(const Anatomy& anatomy, const std::string& anatomy_file, const Parameters& params,
                        std::shared_ptr<const TensionLaw> law) {
  if (!law && params.tension_law) law = std::make_shared<ExtendedTensionLaw>(*params.tension_law);
  try {
    return buildColonModel(anatomy, params.colon, std::move(law));
  } catch (const std::invalid_argument& e) {
    throw InputError(anatomy_file + ": " + e.what() + " (with parameters " + params.file + ")");
  }
}
}  // namespace colosim

namespace colosim {
WorldModel loadWorldModel(const std::string& anatomy_path, const Parameters& params,
                          std::shared_ptr<const TensionLaw> law) {
  ColonModel colon = loadColonModel(anatomy_path, params, std::move(law));
  try {
    return makeWorldModel(std::move(colon), params.scope, params.contact);
  } catch (const std::invalid_argument& e) {
    throw InputError(params.file + ": " + e.what());
  }
}
}  // namespace colosim
