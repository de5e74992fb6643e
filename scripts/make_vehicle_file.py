#!/usr/bin/env python3
"""Regenerate resources/hmmwv.json (the vehicle file the model reads) from the shared HMMWV data set.

    python3 scripts/make_vehicle_file.py data/hmmwv/hmmwv.json > resources/hmmwv.json

Only numbers the model uses are copied, each under a key that names its unit. The STI tire coefficients
are the fit of docs/physics.md §6.5 to the TMeasy C++ block (A1, A2 through dfy0 at pn and 2pn; c_s = dfx0/pn),
rounded as in docs/physics.md's table (whose reference forces the unit tests match).
"""
import json
import sys

src = json.load(open(sys.argv[1]))
sus = src["suspension"]
POINTS = ["SPINDLE", "UPRIGHT", "UCA_F", "UCA_B", "UCA_U", "UCA_CM", "LCA_F", "LCA_B", "LCA_U", "LCA_CM",
          "SHOCK_C", "SHOCK_A", "SPRING_C", "SPRING_A", "TIEROD_C", "TIEROD_U"]


def body(b):
    if "inertia_moments_kg_m2" in b:
        return {"mass_kg": b["mass_kg"], "inertia_moments_kg_m2": b["inertia_moments_kg_m2"],
                "inertia_products_kg_m2": b["inertia_products_kg_m2"]}
    return {"mass_kg": b["mass_kg"], "inertia_moments_kg_m2": b["inertia_kg_m2"],
            "inertia_products_kg_m2": [0.0, 0.0, 0.0]}


def axle(name, steered):
    a = sus[name]
    b = a["bodies"]
    g = a["derived_geometry"]
    d = a["damper"]
    s = a["spring"]
    return {
        "steered": steered,
        "hardpoints_chassis_frame_m": {p: a["hardpoints_chassis_frame_m"][p] for p in POINTS},
        "lower_arm": body(b["lower_control_arm"]),
        "upper_arm": body(b["upper_control_arm"]),
        "upright": body(b["upright"]),
        "spindle": body(b["spindle"]),
        "axle_shaft_spin_inertia_kg_m2": b["axle_shaft_inertia_kg_m2"],
        "spring": {
            "free_length_m": s["free_length_m"],
            "k1_N_per_m": s["derived_cubic_fit"]["k1_N_per_m"],
            "k3_N_per_m3": s["derived_cubic_fit"]["k3_N_per_m3"],
            "stop_min_length_m": s["stop_min_length_m"],
            "stop_max_length_m": s["stop_max_length_m"],
        },
        "damper": {k: d[k] for k in ["midstroke_compression_Ns_per_m", "midstroke_rebound_Ns_per_m",
                                     "bumpstop_compression_Ns_per_m", "bumpstop_rebound_Ns_per_m",
                                     "engagement_min_length_m", "engagement_max_length_m"]},
        "reference_kinematics": {k: g[k] for k in ["kingpin_inclination_deg", "caster_deg", "camber_gain_deg_per_m",
                                                   "bump_steer_deg_per_m", "spring_motion_ratio_dLspring_dzwheel",
                                                   "spring_length_at_design_m", "damper_length_at_design_m",
                                                   "tierod_length_m"]},
    }


tm = src["tire"]["tmeasy"]["cpp_model_values_derived"]
pn = tm["pn_N"]
# C_alpha(Fz) = A1 Fz - (A1/A2) Fz^2 through (pn, dfy0_pn) and (2pn, dfy0_p2n)
c1, c2 = tm["dfy0_pn"], tm["dfy0_p2n"]
# c1 = A1 pn - B pn^2, c2 = 2 A1 pn - 4 B pn^2  ->  B = (2 c1 - c2) / (2 pn^2), A1 = (c1 + B pn^2) / pn
B = (2 * c1 - c2) / (2 * pn * pn)
A1 = (c1 + B * pn * pn) / pn
A2 = A1 / B
rack = src["steering"]["proposed_rack_for_rt_vehicle"]
out = {
    "name": "HMMWV M1025, four SLA suspensions, kinematic rack (rt-vehicle)",
    "provenance": "Numbers copied or derived from data/hmmwv/hmmwv.json (Project Chrono HMMWV, BSD-3, commit "
                  + src["provenance"]["commit"] + ") by scripts/make_vehicle_file.py. STI coefficients fitted to the "
                  "TMeasy C++ block (physics.md 6.5); relaxation lengths, camber and trail coefficients are "
                  "physics.md defaults [O].",
    "gravity_m_s2": 9.81,
    "chassis": {"mass_kg": src["chassis"]["mass_kg"], "com_m": src["chassis"]["com_location_m"],
                "inertia_moments_kg_m2": src["chassis"]["inertia_moments_kg_m2"],
                "inertia_products_kg_m2": src["chassis"]["inertia_products_kg_m2"]},
    "driver_position_m": src["chassis"]["driver_position_m"],
    "rack": {"mass_kg": rack["rack_mass_kg"],
             "inertia_moments_kg_m2": src["steering"]["rack_pinion_chrono"]["steering_link_inertia_kg_m2"],
             "inertia_products_kg_m2": [0.0, 0.0, 0.0],
             "com_m": rack["rack_axis_point_chassis_m"],
             "travel_limit_m": rack["travel_limit_m"],
             "reference_gain_deg_per_m": rack["gain_at_centre_deg_per_m"]},
    "front": axle("front", True),
    "rear": axle("rear", False),
    "stop_table": {"deflection_m": sus["stop_table"]["table_deflection_m"],
                   "force_N": sus["stop_table"]["table_force_N"]},
    "wheel": {"mass_kg": src["wheel"]["mass_kg"], "inertia_kg_m2": src["wheel"]["inertia_kg_m2"]},
    "tire": {
        "mass_kg": src["tire"]["common"]["mass_kg"],
        "inertia_kg_m2": src["tire"]["common"]["inertia_kg_m2"],
        "unloaded_radius_m": src["tire"]["common"]["unloaded_radius_m"],
        "vertical_stiffness_N_per_m": tm["vertical_stiffness_d1_N_per_m"],
        "vertical_stiffness2_N_per_m2": tm["vertical_stiffness_d2_N_per_m2"],
        "vertical_damping_Ns_per_m": tm["vertical_damping_dz_Ns_per_m"],
        "rolling_resistance": tm["rolling_resistance"],
        "sti": {"a0": 0.0, "a1": round(A1, 3), "a2_N": round(A2, -1), "cs": round(tm["dfx0_pn"] / pn, 2),
                "mu0": tm["mu_0"], "k_mu": 0.124, "k_a": 0.0, "c1": 1.0, "c2": 0.34, "c3": 0.57, "c4": 0.32,
                "c_gamma_per_rad": 0.5, "trail_m": 0.03},
        "relaxation_length_x_m": 0.3,
        "relaxation_length_y_m": 0.5,
        "v_min_m_s": 1.0,
        "low_speed_blend_m_s": [0.5, 2.0],
        "low_speed_damping_Ns_per_m": 12000.0,
    },
    "speed_hold": {"kp_per_s": 5.0, "ki_per_s2": 2.0},
}
json.dump(out, sys.stdout, indent=1)
sys.stdout.write("\n")
