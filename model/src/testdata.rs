//! Published linear models used by the unit tests (the case files carry the same numbers in
//! `flight-refs/`; model/ does no I/O, so the tests keep their own copy).

use crate::analysis::linear::LinearModel;

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

/// Seed 002 Eq. 20: RASCAL's VPM M16, 425 kg, level flight at 60 kn, 2000 ft density altitude,
/// states `[w q u theta Omega]`, control `eta_s`, as printed (4 decimals).
pub fn vpm_eq20() -> LinearModel {
    LinearModel::from_rows(
        names(&["w", "q", "u", "theta", "Omega"]),
        names(&["eta_s"]),
        &[
            vec![-1.2019, 28.6824, -0.2336, 0.1218, -0.3143],
            vec![-0.0239, -1.001, -0.0010, 0.0, -0.0016],
            vec![-0.2388, 0.6993, -0.2579, -9.2219, -0.0518],
            vec![0.0, 1.0, 0.0, 0.0, 0.0],
            vec![0.6692, -1.5088, 0.1557, 0.0, -0.1052],
        ],
        &[
            vec![-29.7685],
            vec![12.4604],
            vec![-15.0729],
            vec![0.0],
            vec![-19.1078],
        ],
    )
    .expect("seed 002 Eq. 20 is a valid model")
}

/// Seed 002 Eq. 26: RASCAL's Puma, 5500 kg, 1900 ft/min autorotative descent at 70 kn IAS,
/// 4000 ft density altitude, states `[w q u theta Omega]`, control `theta_0`, as printed.
pub fn puma_eq26() -> LinearModel {
    LinearModel::from_rows(
        names(&["w", "q", "u", "theta", "Omega"]),
        names(&["theta_0"]),
        &[
            vec![-0.6562, 36.2593, -0.0183, 0.0, -0.3864],
            vec![-0.0084, -0.7597, 0.0049, 0.0, -0.0062],
            vec![-0.0151, -9.6090, -0.0129, -9.2081, 0.0379],
            vec![0.0, 1.0, 0.0, 0.0, 0.0],
            vec![0.1056, -0.0604, 0.0034, 0.0, -0.0677],
        ],
        &[
            vec![-94.1647],
            vec![5.7640],
            vec![-4.2271],
            vec![0.0],
            vec![-0.2007],
        ],
    )
    .expect("seed 002 Eq. 26 is a valid model")
}

/// A light gyroplane for the model's own tests, of VPM M16 proportions (estimated numbers; the
/// shipped aircraft file `aircraft/vpm-m16.yaml` carries the same kind of numbers with their
/// provenance).
pub fn gyroplane() -> crate::aircraft::Aircraft {
    // Long: one aircraft's data written out field by field (a struct literal), nothing to cut
    use crate::aircraft::*;
    use crate::components::airfoil::{Airfoil, AnalyticalSection};
    use crate::components::airframe::{Airframe, Surface, Table2};
    use crate::components::propeller::Propeller;
    use crate::components::rigid_body::MassProperties;
    use crate::components::rotor::{
        Corrections, Distribution, Hub, InflowModel, Numerics, Rotor, WakeModel,
    };
    let d = f64::to_radians;
    let section = |cd0: f64, cd2: f64, stall_deg: f64| {
        Airfoil::Analytical(AnalyticalSection {
            lift_slope_per_rad: 5.73,
            zero_lift_alpha_rad: 0.0,
            cd0,
            cd1_per_rad: 0.0,
            cd2_per_rad2: cd2,
            stall_alpha_rad: d(stall_deg),
            compressibility: None,
        })
    };
    let rotor = Rotor {
        hub: Hub::Teetering,
        blades: 2,
        radius_m: 4.115,
        root_cutout_m: 0.4,
        hinge_offset_m: 0.0,
        chord_m: Distribution::constant(0.22),
        pitch_rad: Distribution::constant(d(2.0)),
        pitch_reference_r_over_r: 0.75,
        flap_inertia_kg_m2: 55.3,
        flap_mass_moment_kg_m: 0.0,
        flap_spring_n_m_per_rad: 0.0,
        precone_rad: d(3.4),
        tip_loss_factor: 0.97,
        airfoil: section(0.011, 0.4, 12.0),
        elements: 10,
        corrections: Corrections::default(),
        yawed_flow_drag: false,
        hub_drag_area_m2: 0.0,
        drag_reynolds_number: None,
    };
    let prop_rotor = Rotor {
        hub: Hub::Rigid,
        blades: 3,
        radius_m: 0.737,
        root_cutout_m: 0.12,
        hinge_offset_m: 0.0,
        chord_m: Distribution::constant(0.08),
        pitch_rad: Distribution {
            stations_r_over_r: vec![0.0, 1.0],
            values: vec![0.60, 0.22],
        },
        pitch_reference_r_over_r: 0.75,
        flap_inertia_kg_m2: 0.3,
        flap_mass_moment_kg_m: 0.0,
        flap_spring_n_m_per_rad: 0.0,
        precone_rad: 0.0,
        tip_loss_factor: 0.97,
        airfoil: section(0.012, 0.5, 14.0),
        elements: 8,
        corrections: Corrections::default(),
        yawed_flow_drag: false,
        hub_drag_area_m2: 0.0,
        drag_reynolds_number: None,
    };
    let table = |f: &dyn Fn(f64, f64) -> f64| {
        let alpha: Vec<f64> = (-6..=6).map(|k| 10.0 * k as f64).collect();
        let beta: Vec<f64> = (-3..=3).map(|k| 10.0 * k as f64).collect();
        let values = alpha
            .iter()
            .map(|a| beta.iter().map(|b| f(d(*a), d(*b))).collect())
            .collect();
        Table2 {
            alpha_deg: alpha,
            beta_deg: beta,
            values,
        }
    };
    let surface = |position_m: [f64; 3], area_m2: f64, control_effectiveness: f64| Surface {
        position_m,
        area_m2,
        lift_slope_per_rad: 3.5,
        incidence_rad: 0.0,
        stall_alpha_rad: d(20.0),
        cd0: 0.012,
        control_effectiveness,
        // Out of the slipstream: the tests that need it set it (the aircraft's tests).
        slipstream_fraction: 0.0,
        wash_gradient: 0.0,
        dynamic_pressure_ratio: 1.0,
    };
    Aircraft {
        mass: MassProperties {
            mass_kg: 450.0,
            ixx_kg_m2: 250.0,
            iyy_kg_m2: 650.0,
            izz_kg_m2: 450.0,
            ixz_kg_m2: 40.0,
        },
        cg_m: [0.0, 0.0, 0.0],
        main_rotor: MainRotor {
            rotor,
            pivot_m: [0.0, 0.0, -1.6],
            spindle_length_m: 0.2,
            collective_shift_rad: 0.0,
            inflow: InflowModel::PetersHaQuang {
                wake: WakeModel::SEED_001,
            },
            inflow_dynamics: Default::default(),
            numerics: Numerics {
                azimuth_step_rad: d(5.0),
                periodic_tolerance: 1e-10,
                max_revolutions: 200,
            },
        },
        propeller: PropellerInstallation {
            propeller: Propeller {
                rotor: prop_rotor,
                blockage: 0.0,
                map: None,
            },
            position_m: [-1.3, 0.0, -0.35],
            drive: Drive::Engine {
                max_power_w: 84_500.0,
                rated_rpm: 2388.0,
                polar_inertia_kg_m2: 1.2,
            },
            rotation: Rotation::Clockwise,
        },
        airframe: Airframe {
            reference_area_m2: 1.0,
            reference_length_m: 1.0,
            reference_span_m: 1.0,
            reference_point_m: [0.0, 0.0, 0.0],
            side_force_centre_m: None,
            coefficients: [
                table(&|a, _| -0.6 - 0.8 * a.sin().powi(2)),
                table(&|_, b| -0.8 * b),
                table(&|a, _| -0.4 * a),
                table(&|_, b| -0.05 * b),
                table(&|a, _| 0.15 * a),
                table(&|_, b| -0.1 * b),
            ],
            munk_yaw_m3: 0.0,
            munk_axial_m3: 0.0,
            munk_centre_m: [0.0; 3],
            tailplane: Some(surface([-2.6, 0.0, -0.2], 0.45, 0.0)),
            fin: Some(surface([-2.8, 0.0, -0.6], 0.7, 0.5)),
        },
        controls: ControlMaps {
            shaft_pitch_rad: LinearMap {
                at_0_percent: d(-2.0),
                at_100_percent: d(18.0),
            },
            shaft_roll_rad: LinearMap {
                at_0_percent: d(-8.0),
                at_100_percent: d(8.0),
            },
            rudder_rad: LinearMap {
                at_0_percent: d(-25.0),
                at_100_percent: d(25.0),
            },
        },
        hub_aoa_factor: None,
    }
}

/// Sea-level air for the tests (ISA density; the speed of sound at 15 deg C, rounded).
pub fn sea_level_air() -> crate::aircraft::Air {
    crate::aircraft::Air {
        density_kg_m3: 1.225,
        speed_of_sound_m_s: 340.3,
    }
}

/// The test gyroplane trimmed in level flight at `airspeed_m_s` in sea-level air.
pub fn trimmed_gyroplane(
    airspeed_m_s: f64,
) -> (crate::aircraft::Aircraft, crate::aircraft::trim::Trim) {
    let a = gyroplane();
    let c = crate::aircraft::trim::Condition {
        airspeed_m_s,
        climb_m_s: 0.0,
        turn_rate_rad_s: 0.0,
        air: sea_level_air(),
    };
    let t = crate::aircraft::trim::trim(&a, c, Default::default())
        .expect("the test gyroplane trims in level flight");
    (a, t)
}

/// The test gyroplane's level-flight condition at 31.3 m/s (70 mph) in sea-level air.
pub fn level_70mph() -> crate::aircraft::trim::Condition {
    crate::aircraft::trim::Condition {
        airspeed_m_s: 31.3,
        climb_m_s: 0.0,
        turn_rate_rad_s: 0.0,
        air: sea_level_air(),
    }
}
