//! Rotor files (`aircraft/*.yaml`): a rotor's data, and where every number comes from.
//!
//! ```yaml
//! id: pca-2-rotor                      # equals the file stem
//! title: Pitcairn PCA-2 autogiro rotor
//! provenance: {source: "NACA TR 487, pp. 12-13"}
//! rotor:
//!   hub: articulated                  # articulated | teetering | rigid
//!   blades: 4
//!   radius_m: 6.858
//!   root_cutout_m: 0.0
//!   hinge_offset_m: 0.0
//!   chord_m: {r_over_r: [0, 0.394, 0.394, 1], values: [0.381, 0.381, 0.5587, 0.5587]}
//!   pitch_deg: {r_over_r: [...], values: [...]}      # a repeated station makes a step
//!   pitch_reference_r_over_r: 0.75                   # where a pitch setting is defined
//!   flap_inertia_kg_m2: 452.8
//!   flap_mass_moment_kg_m: 0.0
//!   flap_spring_n_m_per_rad: 0.0
//!   precone_deg: 0.0
//!   tip_loss_factor: 0.959
//!   airfoil:
//!     analytical: {lift_slope_per_rad: 5.85, zero_lift_alpha_deg: 0, cd0: 0.012,
//!                  cd1_per_rad: 0, cd2_per_rad2: 0, stall_alpha_deg: 12}
//!     # optional in `analytical`: drag_divergence_mach (compressibility: Prandtl-Glauert
//!     # lift and Lock's drag rise above it)
//!     # or table: {alpha_deg: [...], mach: [...], cl: [[...]], cd: [[...]]}
//!   elements: 20
//!   yawed_flow_drag: false                           # optional: drag sees the radial flow too
//!   hub_drag_area_m2: 0.0                            # optional: the hub's flat-plate area
//!   drag_reynolds_number: 2.7e6                      # optional: the Re the section drag holds at
//!   corrections: {profile_drag_scale: 1.0, profile_drag_increment: 0.0,   # optional
//!                 pitch_offset_deg: 0.0, lateral_inflow_offset_m_s: 0.0,
//!                 elastic_twist_deg_per_kpa: 0.0,
//!                 profile_drag_reynolds_exponent: 0.0}   # needs drag_reynolds_number
//! physics:                             # optional: the settings every command, case and fit
//!   inflow: peters_haquang             #   of this rotor runs with (each absent one: its
//!   skew: modulus                      #   default, peters_haquang, signed, momentum)
//!   descent: johnson
//! sources:                             # one entry for every field of `rotor`
//!   blades: "NACA TR 487 p. 12"
//!   hinge_offset_m: "estimated: ..."
//!   physics.skew: "reports/skew-forms.md: ..."   # and one for every setting of `physics`
//! ```
//!
//! A case, a fit, an aircraft file or a command that sets one of `physics` differently says
//! so: a case or fit in its checks' notes, a command in its output; an aircraft file may not
//! (one answer per rotor).

use crate::inputs::reference::{Provenance, check_id};
use crate::inputs::yaml::{self, InputError};
use cierva_model::components::airfoil::{Airfoil, AnalyticalSection, SectionTable};
use cierva_model::components::rotor::{Corrections, Distribution, Rotor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A spanwise distribution as written.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DistributionSpec {
    pub r_over_r: Vec<f64>,
    pub values: Vec<f64>,
}

/// The analytical section as written (angles in degrees).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AnalyticalSpec {
    pub lift_slope_per_rad: f64,
    pub zero_lift_alpha_deg: f64,
    pub cd0: f64,
    pub cd1_per_rad: f64,
    pub cd2_per_rad2: f64,
    pub stall_alpha_deg: f64,
    /// Compressibility: Prandtl-Glauert lift and Lock's drag rise above this drag-divergence
    /// Mach number (absent: an incompressible section).
    #[serde(default)]
    pub drag_divergence_mach: Option<f64>,
}

/// A section: exactly one of the two.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AirfoilSpec {
    #[serde(default)]
    pub analytical: Option<AnalyticalSpec>,
    #[serde(default)]
    pub table: Option<SectionTable>,
}

/// Correction parameters (seed 000 Sec. VII); absent means no correction.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CorrectionsSpec {
    #[serde(default = "one")]
    pub profile_drag_scale: f64,
    #[serde(default)]
    pub profile_drag_increment: f64,
    #[serde(default)]
    pub pitch_offset_deg: f64,
    #[serde(default)]
    pub lateral_inflow_offset_m_s: f64,
    /// Elastic torsion: the tip's pitch change (nose up) per kPa of tip dynamic pressure in
    /// hover, deg/kPa (`cierva_model::components::rotor::elastic_twist_rad`).
    #[serde(default)]
    pub elastic_twist_deg_per_kpa: f64,
    /// The section drag's Reynolds-number exponent `n`: drag times `(Re / Re_ref)^-n`
    /// (`cierva_model::components::rotor::Corrections::profile_drag_reynolds_exponent`).
    #[serde(default)]
    pub profile_drag_reynolds_exponent: f64,
}

fn one() -> f64 {
    1.0
}

/// A rotor as written.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RotorSpec {
    pub hub: cierva_model::components::rotor::Hub,
    pub blades: usize,
    pub radius_m: f64,
    pub root_cutout_m: f64,
    pub hinge_offset_m: f64,
    pub chord_m: DistributionSpec,
    pub pitch_deg: DistributionSpec,
    pub pitch_reference_r_over_r: f64,
    pub flap_inertia_kg_m2: f64,
    pub flap_mass_moment_kg_m: f64,
    pub flap_spring_n_m_per_rad: f64,
    pub precone_deg: f64,
    pub tip_loss_factor: f64,
    pub airfoil: AirfoilSpec,
    pub elements: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corrections: Option<CorrectionsSpec>,
    /// Section drag along the whole relative flow, radial share included (optional, off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yawed_flow_drag: Option<bool>,
    /// The hub's drag as an equivalent flat-plate area, m^2 (optional, none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hub_drag_area_m2: Option<f64>,
    /// The chord Reynolds number at which the airfoil's drag coefficients hold (optional; the
    /// reference of the drag's Reynolds-number exponent, which needs it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag_reynolds_number: Option<f64>,
}

/// A rotor's physics settings as written: in its file (`physics:`), in a case's or a fit's
/// rotor subject, on an aircraft's main rotor, or on the command line; each absent one is
/// left to the next (the rotor file's, then the default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicsSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inflow: Option<InflowSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skew: Option<SkewSpec>,
    /// The wake's mass flow in descent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub descent: Option<DescentSpec>,
}

/// A rotor's physics settings, resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Physics {
    pub inflow: InflowSpec,
    pub skew: SkewSpec,
    pub descent: DescentSpec,
}

impl Physics {
    /// The model's inflow model with these settings.
    pub fn model(&self) -> cierva_model::components::rotor::InflowModel {
        self.inflow.model(self.skew, self.descent)
    }
}

impl PhysicsSpec {
    /// Each setting in words (`skew: modulus`), with its value as the files write it.
    fn stated(&self) -> Vec<(&'static str, String)> {
        let name = |v: serde_yaml::Value| v.as_str().unwrap_or_default().to_string();
        let mut out = Vec::new();
        if let Some(i) = self.inflow {
            out.push(("inflow", name(serde_yaml::to_value(i).unwrap_or_default())));
        }
        if let Some(k) = self.skew {
            out.push(("skew", name(serde_yaml::to_value(k).unwrap_or_default())));
        }
        if let Some(d) = self.descent {
            out.push(("descent", name(serde_yaml::to_value(d).unwrap_or_default())));
        }
        out
    }

    /// These settings over the rotor file's (`physics:`) and the defaults: each one stated here
    /// replaces the file's. With, in words, every one that differs from what the file runs
    /// with, `who` naming what sets it ("the case", "--skew").
    pub fn over(&self, file: &RotorFile, who: &str) -> (Physics, Vec<String>) {
        let (physics, named) = self.over_named(file, who);
        (physics, named.into_iter().map(|(_, words)| words).collect())
    }

    /// [`Self::over`], each override with the setting's name (`skew`).
    pub fn over_named(
        &self,
        file: &RotorFile,
        who: &str,
    ) -> (Physics, Vec<(&'static str, String)>) {
        let base = file.physics();
        let mine = Physics {
            inflow: self.inflow.unwrap_or(base.inflow),
            skew: self.skew.unwrap_or(base.skew),
            descent: self.descent.unwrap_or(base.descent),
        };
        let theirs: std::collections::BTreeMap<_, _> = file.physics.stated().into_iter().collect();
        let base_words: std::collections::BTreeMap<_, _> = PhysicsSpec {
            inflow: Some(base.inflow),
            skew: Some(base.skew),
            descent: Some(base.descent),
        }
        .stated()
        .into_iter()
        .collect();
        let notes = self
            .stated()
            .into_iter()
            .filter(|(k, v)| base_words.get(k) != Some(v))
            .map(|(k, v)| {
                let was = match theirs.get(k) {
                    Some(t) => format!("the rotor file's {t}"),
                    None => format!(
                        "the default {} (the rotor file states none)",
                        base_words.get(k).map_or("", |s| s.as_str())
                    ),
                };
                let words = format!(
                    "{who} sets `{k}: {v}` over {was} ({}): the rotor's answer differs from \
                     what its file gives",
                    file.path.display()
                );
                (k, words)
            })
            .collect();
        (mine, notes)
    }
}

/// A rotor file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotorFileSpec {
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    pub rotor: RotorSpec,
    /// The physics settings every command, case and fit of this rotor runs with.
    #[serde(default)]
    pub physics: PhysicsSpec,
    pub sources: BTreeMap<String, String>,
    /// Plausible ranges of the estimated parameters
    /// ([`crate::inputs::parameters::ROTOR_PARAMETERS`]), each with its source and distribution, as an
    /// aircraft file's: the inputs `cierva uncertainty` propagates through a rotor case.
    #[serde(default)]
    pub ranges: BTreeMap<String, crate::inputs::ranges::RangeSpec>,
}

/// A loaded rotor file.
#[derive(Debug, Clone, PartialEq)]
pub struct RotorFile {
    pub path: PathBuf,
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    pub rotor: Rotor,
    /// The physics settings it states (each absent one: its default).
    pub physics: PhysicsSpec,
    pub sources: BTreeMap<String, String>,
    /// Plausible ranges of its estimated parameters, by name.
    pub ranges: BTreeMap<String, crate::inputs::ranges::Range>,
}

impl RotorFile {
    /// The physics settings the rotor runs with: its file's, each absent one at its default.
    pub fn physics(&self) -> Physics {
        let d = Physics::default();
        Physics {
            inflow: self.physics.inflow.unwrap_or(d.inflow),
            skew: self.physics.skew.unwrap_or(d.skew),
            descent: self.physics.descent.unwrap_or(d.descent),
        }
    }
}

/// Loads and checks a rotor file.
pub fn load(path: &Path) -> Result<RotorFile, InputError> {
    let src = yaml::read(path)?;
    let spec: RotorFileSpec = yaml::parse(path, &src)?;
    check_id(path, &src, &spec.id)?;
    let err = |field: &str, msg: String| InputError::field(path, &src, field, msg);
    check_sources(path, &spec, &err)?;
    let r = &spec.rotor;
    let dist = |d: &DistributionSpec, scale: f64| Distribution {
        stations_r_over_r: d.r_over_r.clone(),
        values: d.values.iter().map(|v| v * scale).collect(),
    };
    let airfoil = match (&r.airfoil.analytical, &r.airfoil.table) {
        (Some(a), None) => Airfoil::Analytical(AnalyticalSection {
            lift_slope_per_rad: a.lift_slope_per_rad,
            zero_lift_alpha_rad: a.zero_lift_alpha_deg.to_radians(),
            cd0: a.cd0,
            cd1_per_rad: a.cd1_per_rad,
            cd2_per_rad2: a.cd2_per_rad2,
            stall_alpha_rad: a.stall_alpha_deg.to_radians(),
            compressibility: a.drag_divergence_mach.map(|m| {
                cierva_model::components::airfoil::Compressibility {
                    drag_divergence_mach: m,
                }
            }),
        }),
        (None, Some(t)) => Airfoil::Table(t.clone()),
        _ => {
            return Err(err(
                "rotor.airfoil",
                "give exactly one of `analytical` or `table`".into(),
            ));
        }
    };
    let corrections = r
        .corrections
        .as_ref()
        .map_or_else(Corrections::default, |c| Corrections {
            profile_drag_scale: c.profile_drag_scale,
            profile_drag_increment: c.profile_drag_increment,
            pitch_offset_rad: c.pitch_offset_deg.to_radians(),
            lateral_inflow_offset_m_s: c.lateral_inflow_offset_m_s,
            elastic_twist_rad_per_pa: c.elastic_twist_deg_per_kpa.to_radians() / 1000.0,
            profile_drag_reynolds_exponent: c.profile_drag_reynolds_exponent,
        });
    let rotor = Rotor {
        hub: r.hub,
        blades: r.blades,
        radius_m: r.radius_m,
        root_cutout_m: r.root_cutout_m,
        hinge_offset_m: r.hinge_offset_m,
        chord_m: dist(&r.chord_m, 1.0),
        pitch_rad: dist(&r.pitch_deg, 1f64.to_radians()),
        pitch_reference_r_over_r: r.pitch_reference_r_over_r,
        flap_inertia_kg_m2: r.flap_inertia_kg_m2,
        flap_mass_moment_kg_m: r.flap_mass_moment_kg_m,
        flap_spring_n_m_per_rad: r.flap_spring_n_m_per_rad,
        precone_rad: r.precone_deg.to_radians(),
        tip_loss_factor: r.tip_loss_factor,
        airfoil,
        elements: r.elements,
        corrections,
        yawed_flow_drag: r.yawed_flow_drag.unwrap_or(false),
        hub_drag_area_m2: r.hub_drag_area_m2.unwrap_or(0.0),
        drag_reynolds_number: r.drag_reynolds_number,
    };
    rotor.validate().map_err(|e| {
        use cierva_model::components::rotor::RotorError;
        let field = match &e {
            RotorError::Invalid { name, .. } | RotorError::TooMany { name, .. } => {
                format!("rotor.{}", written_name(name))
            }
            RotorError::Distribution(n) => format!("rotor.{}", written_name(n)),
            RotorError::Airfoil(_) => "rotor.airfoil".into(),
            _ => "rotor".into(),
        };
        err(&field, e.to_string())
    })?;
    let ranges = checked_ranges(&spec, &rotor, &err)?;
    Ok(RotorFile {
        path: path.to_path_buf(),
        id: spec.id,
        title: spec.title,
        provenance: spec.provenance,
        rotor,
        physics: spec.physics,
        sources: spec.sources,
        ranges,
    })
}

/// Every field of a rotor file's `rotor` and every setting of its `physics` has a source, and
/// every source names one of them.
fn check_sources(
    path: &Path,
    spec: &RotorFileSpec,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<(), InputError> {
    let written =
        serde_yaml::to_value(&spec.rotor).map_err(|e| InputError::file(path, e.to_string()))?;
    let fields: Vec<String> = written
        .as_mapping()
        .map(|m| {
            m.keys()
                .filter_map(|k| k.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    let settings: Vec<String> = spec
        .physics
        .stated()
        .into_iter()
        .map(|(k, _)| format!("physics.{k}"))
        .collect();
    let numbers = fields.iter().map(|f| {
        let what = "say where the number comes from (or \"estimated: why\")";
        (f, format!("rotor.{f}"), what)
    });
    let chosen = settings.iter().map(|f| {
        let what = "say what it was chosen on (a report, a comparison, a paper)";
        (f, f.clone(), what)
    });
    for (key, at, what) in numbers.chain(chosen) {
        if spec.sources.get(key).is_none_or(|s| s.trim().is_empty()) {
            return Err(err(
                &at,
                format!("`{key}` has no entry under `sources`: {what}"),
            ));
        }
    }
    if let Some(extra) = spec
        .sources
        .keys()
        .find(|k| !fields.contains(k) && !settings.contains(k))
    {
        return Err(err(
            &format!("sources.{extra}"),
            match extra.strip_prefix("physics.") {
                Some(_) => format!("`{extra}` is not a setting `physics` states"),
                None => format!("`{extra}` is not a field of `rotor`"),
            },
        ));
    }
    Ok(())
}

/// A rotor field's name as the file writes it, from the model's (which holds angles in radians
/// where the file gives degrees).
fn written_name(model: &str) -> &str {
    match model {
        "precone_rad" => "precone_deg",
        "pitch_rad" => "pitch_deg",
        "corrections.pitch_offset_rad" => "corrections.pitch_offset_deg",
        "corrections.elastic_twist_rad_per_pa" => "corrections.elastic_twist_deg_per_kpa",
        // A product of counts is pointed at its last factor, the one most often raised.
        "blades x elements" => "elements",
        other => other,
    }
}

/// A rotor file's ranges, checked as an aircraft file's are, and only on parameters whose
/// source calls them estimated (a measured value is not an uncertain input).
fn checked_ranges(
    spec: &RotorFileSpec,
    rotor: &Rotor,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<BTreeMap<String, crate::inputs::ranges::Range>, InputError> {
    let names: Vec<String> = crate::inputs::parameters::ROTOR_PARAMETERS
        .iter()
        .map(|p| p.name.to_string())
        .collect();
    let ranges = crate::inputs::ranges::checked(
        &spec.ranges,
        &|name| crate::inputs::parameters::rotor_parameter(rotor, name),
        &names,
        "this rotor",
        err,
    )?;
    for name in ranges.keys() {
        let estimated = spec
            .sources
            .get(name.split('.').next().unwrap_or(name))
            .is_some_and(|s| s.to_lowercase().contains("estimated"));
        if !estimated {
            return Err(err(
                &format!("ranges.{name}"),
                format!(
                    "`{name}` has a source that does not call it estimated: a measured value is \
                     not an uncertain input here"
                ),
            ));
        }
    }
    Ok(ranges)
}

/// Inflow models for rotor subjects (in case files and on the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum InflowSpec {
    /// Peters-HaQuang, uniform and first harmonics.
    #[default]
    PetersHaquang,
    /// Peters-HaQuang with the harmonics zeroed.
    Uniform,
}

/// Skew-angle conventions (in case files and on the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum SkewSpec {
    /// Seed 001 Eq. 15: chi = atan(V / (v_i0m - w_hub)), negative in autorotation;
    /// discontinuous where the flow through the disc changes direction.
    #[default]
    Signed,
    /// Seed 003 Eq. 5 as Chen presents it: chi = atan2(V, v_i0m - w_hub), above 90 deg in
    /// autorotation; singular in axial upflow (vertical descent).
    Geometric,
    /// Seed 003 Eq. 6: tan alpha = |v_i0m - w_hub| / V, chi = 90 deg - alpha.
    Modulus,
}

/// The wake's mass flow in descent (in case, aircraft and fit files and on the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum DescentSpec {
    /// Momentum theory throughout (Peters and HaQuang as published): no physical solution in
    /// the vortex-ring and turbulent-wake states.
    #[default]
    Momentum,
    /// Johnson's empirical induced velocity in axial descent (Helicopter Theory, 1980),
    /// blended into the mass flow below an in-plane speed of v_h.
    Johnson,
}

impl DescentSpec {
    /// Momentum theory (the default).
    pub fn is_momentum(&self) -> bool {
        *self == Self::Momentum
    }
}

impl InflowSpec {
    /// The model's inflow model with this skew convention and descent mass flow.
    pub fn model(
        self,
        skew: SkewSpec,
        descent: DescentSpec,
    ) -> cierva_model::components::rotor::InflowModel {
        use cierva_model::components::rotor::{
            DescentInflow, InflowModel, SkewConvention, WakeModel,
        };
        let wake = WakeModel {
            skew: match skew {
                SkewSpec::Signed => SkewConvention::Signed,
                SkewSpec::Geometric => SkewConvention::Geometric,
                SkewSpec::Modulus => SkewConvention::Modulus,
            },
            descent: match descent {
                DescentSpec::Momentum => DescentInflow::Momentum,
                DescentSpec::Johnson => DescentInflow::Johnson,
            },
        };
        match self {
            Self::PetersHaquang => InflowModel::PetersHaQuang { wake },
            Self::Uniform => InflowModel::UniformOnly { wake },
        }
    }
}
