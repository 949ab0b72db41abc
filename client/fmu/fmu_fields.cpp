/// The per-kind field table of FMU configurations (positions: demlink_c.h, "Generic layout").
#include "fmu_fields.hpp"

#include <map>
#include <stdexcept>

namespace demlink::fmu {
namespace {

using A = FieldArray;
using T = FieldType;

/// A box or sphere region that may ride on a body: the sink's and the region sensor's
/// fields share one generic layout.
std::vector<FieldSpec> regionFields() {
  return {
      {"shape", T::kChoice, A::kInts, 0, 1, "", {{"box", 0}, {"sphere", 1}}},
      {"centre", T::kReal, A::kReals, 1, 3, "m", {}, {}, {}, true},
      {"size", T::kReal, A::kReals, 4, 3, "m", {}, {"shape", "box"}},
      {"orientation", T::kReal, A::kReals, 7, 4, "", {}, {"shape", "box"}},
      {"radius", T::kReal, A::kReals, 4, 1, "m", {}, {"shape", "sphere"}},
      {"velocity", T::kReal, A::kReals, 11, 3, "m/s"},
      {"attached_to", T::kText, A::kStrings, 2},
  };
}

const std::map<std::string, std::vector<FieldSpec>>& table() {
  static const std::map<std::string, std::vector<FieldSpec>> fields = {
      {"simulation_box",
       {
           {"time_step", T::kReal, A::kReals, 1, 1, "s"},
           {"end_time", T::kReal, A::kReals, 2, 1, "s", {}, {}, {0.0}},
           {"gravity", T::kReal, A::kReals, 3, 3, "m/s2", {}, {}, {0.0, 0.0, -9.81}},
           {"bounds_lower", T::kReal, A::kReals, 6, 3, "m"},
           {"bounds_upper", T::kReal, A::kReals, 9, 3, "m"},
           {"vtk_interval", T::kReal, A::kReals, 12, 1, "s"},
           {"restitution_tolerance", T::kReal, A::kReals, 13, 1, ""},
           {"max_impact_velocity", T::kReal, A::kReals, 14, 1, "m/s"},
           {"coarse_graining", T::kReal, A::kReals, 15, 1, ""},
           {"max_overlap_fraction", T::kReal, A::kReals, 16, 1, ""},
           {"modulus_scale", T::kReal, A::kReals, 17, 1, ""},
           {"expected_count", T::kInteger, A::kInts, 0},
           {"threads", T::kInteger, A::kInts, 1},
           {"contact_model",
            T::kChoice,
            A::kInts,
            2,
            1,
            "",
            {{"default", 0}, {"hertz_mindlin", 1}, {"linear_spring_dashpot", 2}}},
           {"integrator", T::kChoice, A::kInts, 3, 1, "", {{"default", 0}, {"velocity_verlet", 1}, {"explicit_euler", 2}}},
           {"fidelity",
            T::kChoice,
            A::kInts,
            4,
            1,
            "",
            {{"none", 0}, {"draft", 1}, {"engineering", 2}, {"validation", 3}}},
           {"expected_names", T::kTextList, A::kStrings, 2},
       }},
      {"material",
       {
           {"database_name", T::kText, A::kStrings, 2},
           {"density", T::kReal, A::kReals, 1, 1, "kg/m3"},
           {"youngs_modulus", T::kReal, A::kReals, 2, 1, "Pa"},
           {"poisson_ratio", T::kReal, A::kReals, 3, 1, ""},
           {"restitution", T::kReal, A::kReals, 4, 1, ""},
           {"sliding_friction", T::kReal, A::kReals, 5, 1, ""},
           {"rolling_friction", T::kReal, A::kReals, 6, 1, ""},
       }},
      {"plane",
       {
           {"material", T::kText, A::kStrings, 2, 1, "", {}, {}, {}, true},
           {"point", T::kReal, A::kReals, 1, 3, "m", {}, {}, {}, true},
           {"normal", T::kReal, A::kReals, 4, 3, "", {}, {}, {}, true},
       }},
      {"single_particle",
       {
           {"material", T::kText, A::kStrings, 2, 1, "", {}, {}, {}, true},
           {"position", T::kReal, A::kReals, 1, 3, "m", {}, {}, {}, true},
           {"velocity", T::kReal, A::kReals, 4, 3, "m/s", {}, {}, {0.0, 0.0, 0.0}},
           {"diameter", T::kReal, A::kReals, 7, 1, "m", {}, {}, {}, true},
       }},
      {"particle_system",
       {
           {"file", T::kText, A::kStrings, 2, 1, "", {}, {}, {}, true},
           {"format", T::kChoice, A::kInts, 0, 1, "", {{"csv", 0}, {"checkpoint", 1}}},
       }},
      {"particle_source",
       {
           {"material", T::kText, A::kStrings, 2, 1, "", {}, {}, {}, true},
           {"attached_to", T::kText, A::kStrings, 3},
           {"clump_template", T::kText, A::kStrings, 4},
           {"region", T::kChoice, A::kInts, 1, 1, "", {{"box", 0}, {"disc", 1}}},
           {"centre", T::kReal, A::kReals, 1, 3, "m", {}, {}, {}, true},
           {"half_extents", T::kReal, A::kReals, 4, 3, "m", {}, {"region", "box"}},
           {"normal", T::kReal, A::kReals, 4, 3, "", {}, {"region", "disc"}},
           {"radius_min", T::kReal, A::kReals, 7, 1, "m", {}, {}, {}, true},
           {"radius_max", T::kReal, A::kReals, 8, 1, "m", {}, {}, {}, true},
           {"rate", T::kReal, A::kReals, 9, 1, "1/s"},
           {"mass_rate", T::kReal, A::kReals, 10, 1, "kg/s"},
           {"velocity", T::kReal, A::kReals, 11, 3, "m/s"},
           {"start_time", T::kReal, A::kReals, 14, 1, "s"},
           {"stop_time", T::kReal, A::kReals, 15, 1, "s"},
           {"disc_radius", T::kReal, A::kReals, 16, 1, "m", {}, {"region", "disc"}},
           {"disc_thickness", T::kReal, A::kReals, 17, 1, "m", {}, {"region", "disc"}},
           {"seed", T::kInteger, A::kInts, 0},
       }},
      {"particle_sink", regionFields()},
      {"region_sensor", regionFields()},
      {"flow_sensor",
       {
           {"shape", T::kChoice, A::kInts, 0, 1, "", {{"rectangle", 0}, {"disc", 1}}},
           {"centre", T::kReal, A::kReals, 1, 3, "m", {}, {}, {}, true},
           {"normal", T::kReal, A::kReals, 4, 3, "", {}, {}, {}, true},
           {"length", T::kReal, A::kReals, 7, 1, "m", {}, {"shape", "rectangle"}},
           {"width", T::kReal, A::kReals, 8, 1, "m", {}, {"shape", "rectangle"}},
           {"length_axis", T::kReal, A::kReals, 9, 3, "", {}, {"shape", "rectangle"}},
           {"radius", T::kReal, A::kReals, 7, 1, "m", {}, {"shape", "disc"}},
           {"velocity", T::kReal, A::kReals, 12, 3, "m/s"},
           {"attached_to", T::kText, A::kStrings, 2},
       }},
      {"pit_generator",
       {
           {"material", T::kText, A::kStrings, 2, 1, "", {}, {}, {}, true},
           {"lower", T::kReal, A::kReals, 1, 3, "m", {}, {}, {}, true},
           {"upper", T::kReal, A::kReals, 4, 3, "m", {}, {}, {}, true},
           {"radius_min", T::kReal, A::kReals, 7, 1, "m", {}, {}, {}, true},
           {"radius_max", T::kReal, A::kReals, 8, 1, "m", {}, {}, {}, true},
           {"target_height", T::kReal, A::kReals, 9, 1, "m", {}, {}, {}, true},
           {"seed", T::kInteger, A::kInts, 0},
           {"clod_fraction", T::kReal, A::kReals, 10, 1, ""},
           {"clod_radius", T::kReal, A::kReals, 11, 1, "m"},
           {"clod_bonds", T::kText, A::kStrings, 3},
           {"clump_template", T::kText, A::kStrings, 4},
       }},
      {"clump_template",
       {
           {"spheres", T::kRealList, A::kReals, 1, 4, "m", {}, {}, {}, true},
       }},
      {"parallel_bonds",
       {
           {"normal_stiffness_per_area", T::kReal, A::kReals, 1, 1, "Pa/m", {}, {}, {}, true},
           {"shear_stiffness_per_area", T::kReal, A::kReals, 2, 1, "Pa/m", {}, {}, {}, true},
           {"tensile_strength", T::kReal, A::kReals, 3, 1, "Pa", {}, {}, {}, true},
           {"shear_strength", T::kReal, A::kReals, 4, 1, "Pa", {}, {}, {}, true},
           {"gap_tolerance", T::kReal, A::kReals, 5, 1, "m", {}, {}, {}, true},
           {"radius_multiplier", T::kReal, A::kReals, 6, 1, ""},
           {"create_time", T::kReal, A::kReals, 7, 1, "s"},
           {"fraction", T::kReal, A::kReals, 8, 1, ""},
           {"seed", T::kInteger, A::kInts, 0},
           // Always written (its default, everywhere, when unset): the layout whose
           // strings[2] is the attached body and whose materials follow it.
           {"region", T::kChoice, A::kInts, 1, 1, "", {{"none", 0}, {"box", 1}, {"sphere", 2}}, {}, {0.0}},
           {"region_centre", T::kReal, A::kReals, 9, 3, "m"},
           {"region_size", T::kReal, A::kReals, 12, 3, "m", {}, {"region", "box"}},
           {"region_orientation", T::kReal, A::kReals, 15, 4, "", {}, {"region", "box"}},
           {"region_radius", T::kReal, A::kReals, 12, 1, "m", {}, {"region", "sphere"}},
           {"region_attached_to", T::kText, A::kStrings, 2},
           {"materials", T::kTextList, A::kStrings, 3},
       }},
      {"rigid_body",
       {
           {"material", T::kText, A::kStrings, 2, 1, "", {}, {}, {}, true},
           {"geometry",
            T::kChoice,
            A::kInts,
            0,
            1,
            "",
            {{"server_stl", 0}, {"box", 1}, {"client_stl", 2}},
            {},
            {},
            true},
           {"stl_file", T::kText, A::kStrings, 3},
           {"size", T::kReal, A::kReals, 11, 3, "m", {}, {"geometry", "box"}},
           {"motion", T::kChoice, A::kInts, 1, 1, "", {{"predicted", 1}, {"lagged", 2}}},
           {"reference_point", T::kReal, A::kReals, 1, 3, "m", {}, {}, {0.0, 0.0, 0.0}},
           {"position", T::kReal, A::kReals, 4, 3, "m", {}, {}, {0.0, 0.0, 0.0}},
           {"orientation", T::kReal, A::kReals, 7, 4, "", {}, {}, {1.0, 0.0, 0.0, 0.0}},
       }},
  };
  return fields;
}

}  // namespace

const std::vector<FieldSpec>& fieldsOf(const std::string& kind) {
  const auto it = table().find(kind);
  if (it == table().end()) throw std::invalid_argument("component kind '" + kind + "' has no named fields");
  return it->second;
}

}  // namespace demlink::fmu
