//! The model's empirical corrections as one set, and the corrections file `cierva fit` writes
//! and `cierva validate --corrections` reads.
//!
//! A [`CorrectionSet`] names the corrections it sets; the rest stay as the aircraft or rotor
//! file gives them. Aircraft corrections (propeller blockage, hub angle-of-attack factor) need an
//! aircraft; blade corrections (profile drag, pitch offset, lateral inflow offset, elastic
//! twist) and the hub's drag area act on the main rotor wherever it flies, in an aircraft or
//! alone in a tunnel.
//!
//! A set can also carry values of an aircraft file's *estimated* physical parameters (the
//! names of [`crate::inputs::parameters::PARAMETERS`]: a fin's area, the pod's side-force centre, an
//! inertia), as a fit of them writes; they too need an aircraft. The aircraft file itself keeps
//! its estimates: a fitted value is an overlay that `cierva validate --corrections` applies and
//! the report names.
//!
//! # Corrections file
//! ```yaml
//! id: vpm-m16-seed000-fit
//! title: Propeller blockage and hub factor fitted to seed 000's X_u and Z_w
//! applies_to: {aircraft: vpm-m16}      # or {rotor: pca-2}: the file id it corrects, or
//!                                      # {model: "command: python3 model.py --serve"}: a model
//!                                      # behind the model interface, as its cases write it
//! corrections:
//!   propeller_blockage: 0.97
//!   hub_aoa_factor: 0.55
//!   estimated: {airframe.fin.area_m2: 0.64}   # optional: estimated physical parameters
//!                                             # (an aircraft's; names as `cierva sensitivity`)
//! provenance:
//!   source: "fitted by `cierva fit fits/vpm-m16-seed000.yaml` ..."
//! fit: {...}                           # optional: the fit's status, standard errors, costs
//! ```
//!
//! A model behind the model interface takes its declared parameters by name
//! (`corrections: {parameters: {blockage_factor: 0.85}}`, and nothing else): `validate
//! --corrections` sends them with every request to the cases whose model is written as
//! `applies_to.model` says.

use crate::inputs::reference::Provenance;
use crate::inputs::yaml::{self, InputError};
use cierva_model::aircraft::Aircraft;
use cierva_model::components::rotor::Rotor;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Every correction of an aircraft by its name as written: its unit and meaning (cierva's
/// aircraft declares each through the model interface as `corrections.<name>`).
pub const CORRECTIONS: [(&str, &str, &str); 9] = [
    (
        "propeller_blockage",
        "-",
        "seed 000's propeller blockage: the fraction of the free stream the rotor's wake takes from the propeller disc (0 none, 1 total)",
    ),
    (
        "hub_aoa_factor",
        "-",
        "seed 000's hub angle of attack as a factor on the c.g.'s (the free stream's angle at the hub; what pitch rate adds stays kinematic, so 1 is no correction)",
    ),
    (
        "profile_drag_scale",
        "-",
        "multiplies the main rotor's section drag coefficient",
    ),
    (
        "profile_drag_increment",
        "-",
        "added to the main rotor's section drag coefficient",
    ),
    (
        "pitch_offset_deg",
        "deg",
        "added to the main rotor's blade pitch",
    ),
    (
        "lateral_inflow_offset_m_s",
        "m/s",
        "added to the main rotor's lateral induced velocity v1s (seed 003)",
    ),
    (
        "elastic_twist_deg_per_kpa",
        "deg/kPa",
        "the main rotor's elastic torsion: the tip's pitch change per kPa of tip dynamic pressure in hover",
    ),
    (
        "hub_drag_area_m2",
        "m^2",
        "the main rotor's hub drag as an equivalent flat-plate area",
    ),
    (
        "profile_drag_reynolds_exponent",
        "-",
        "the main rotor's section-drag Reynolds-number exponent",
    ),
];

/// Corrections to set (those given; the others as the file has them).
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CorrectionSet {
    /// Seed 000 Sec. VII.A: the fraction of the free stream the rotor's wake takes from the
    /// propeller disc (0 none, 1 total).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub propeller_blockage: Option<f64>,
    /// Seed 000 Sec. VII.A: the hub's angle of attack as a factor on the c.g.'s (omit for the
    /// kinematic angle).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hub_aoa_factor: Option<f64>,
    /// Multiplies the main rotor's section drag coefficient.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile_drag_scale: Option<f64>,
    /// Added to the main rotor's section drag coefficient.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile_drag_increment: Option<f64>,
    /// Added to the main rotor's blade pitch, deg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitch_offset_deg: Option<f64>,
    /// Added to the main rotor's lateral induced velocity `v1s`, m/s (seed 003).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lateral_inflow_offset_m_s: Option<f64>,
    /// The main rotor's elastic torsion: the tip's pitch change (nose up) per kPa of tip
    /// dynamic pressure in hover, deg/kPa.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elastic_twist_deg_per_kpa: Option<f64>,
    /// The main rotor's hub drag as an equivalent flat-plate area, m^2 (replaces the rotor
    /// file's `hub_drag_area_m2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hub_drag_area_m2: Option<f64>,
    /// The main rotor's section-drag Reynolds-number exponent `n`: drag times
    /// `(Re / Re_ref)^-n`, `Re_ref` the rotor file's `drag_reynolds_number`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile_drag_reynolds_exponent: Option<f64>,
    /// An aircraft's estimated physical parameters, by their names in
    /// [`crate::inputs::parameters::PARAMETERS`].
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub estimated: BTreeMap<String, f64>,
    /// A model's declared parameters, by the names it declares
    /// ([`crate::external::FlightModel::parameters`]): what a fit of a model behind the model
    /// interface writes, and what `validate --corrections` sends with every request to it.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub parameters: BTreeMap<String, f64>,
}

impl CorrectionSet {
    /// Whether it names an aircraft correction or parameter (which an isolated rotor cannot
    /// take).
    pub fn needs_aircraft(&self) -> bool {
        self.propeller_blockage.is_some()
            || self.hub_aoa_factor.is_some()
            || !self.estimated.is_empty()
    }

    /// The same set with `over`'s corrections replacing this one's where `over` gives them.
    pub fn overridden_by(&self, over: &CorrectionSet) -> CorrectionSet {
        CorrectionSet {
            propeller_blockage: over.propeller_blockage.or(self.propeller_blockage),
            hub_aoa_factor: over.hub_aoa_factor.or(self.hub_aoa_factor),
            profile_drag_scale: over.profile_drag_scale.or(self.profile_drag_scale),
            profile_drag_increment: over.profile_drag_increment.or(self.profile_drag_increment),
            pitch_offset_deg: over.pitch_offset_deg.or(self.pitch_offset_deg),
            lateral_inflow_offset_m_s: over
                .lateral_inflow_offset_m_s
                .or(self.lateral_inflow_offset_m_s),
            elastic_twist_deg_per_kpa: over
                .elastic_twist_deg_per_kpa
                .or(self.elastic_twist_deg_per_kpa),
            hub_drag_area_m2: over.hub_drag_area_m2.or(self.hub_drag_area_m2),
            profile_drag_reynolds_exponent: over
                .profile_drag_reynolds_exponent
                .or(self.profile_drag_reynolds_exponent),
            estimated: {
                let mut e = self.estimated.clone();
                e.extend(over.estimated.iter().map(|(k, v)| (k.clone(), *v)));
                e
            },
            parameters: {
                let mut e = self.parameters.clone();
                e.extend(over.parameters.iter().map(|(k, v)| (k.clone(), *v)));
                e
            },
        }
    }

    /// Every correction an aircraft has, at its value (in the units written; the hub
    /// angle-of-attack factor at 1 where the aircraft leaves it unset, which is the same model).
    pub fn of_aircraft(a: &Aircraft) -> Self {
        let c = &a.main_rotor.rotor.corrections;
        Self {
            propeller_blockage: Some(a.propeller.propeller.blockage),
            hub_aoa_factor: Some(a.hub_aoa_factor.unwrap_or(1.0)),
            profile_drag_scale: Some(c.profile_drag_scale),
            profile_drag_increment: Some(c.profile_drag_increment),
            pitch_offset_deg: Some(c.pitch_offset_rad.to_degrees()),
            lateral_inflow_offset_m_s: Some(c.lateral_inflow_offset_m_s),
            elastic_twist_deg_per_kpa: Some(c.elastic_twist_rad_per_pa.to_degrees() * 1000.0),
            hub_drag_area_m2: Some(a.main_rotor.rotor.hub_drag_area_m2),
            profile_drag_reynolds_exponent: Some(c.profile_drag_reynolds_exponent),
            ..Self::default()
        }
    }

    /// Every correction an isolated rotor has, at its value (in the units written): its blade
    /// corrections and its hub's drag area ([`Self::apply_to_rotor`] sets the same).
    pub fn of_rotor(r: &Rotor) -> Self {
        let c = &r.corrections;
        Self {
            profile_drag_scale: Some(c.profile_drag_scale),
            profile_drag_increment: Some(c.profile_drag_increment),
            pitch_offset_deg: Some(c.pitch_offset_rad.to_degrees()),
            lateral_inflow_offset_m_s: Some(c.lateral_inflow_offset_m_s),
            elastic_twist_deg_per_kpa: Some(c.elastic_twist_rad_per_pa.to_degrees() * 1000.0),
            hub_drag_area_m2: Some(r.hub_drag_area_m2),
            profile_drag_reynolds_exponent: Some(c.profile_drag_reynolds_exponent),
            ..Self::default()
        }
    }

    /// The set as values of declared parameters, by the names a model behind the model
    /// interface declares them: each correction given as `corrections.<name>` and each
    /// estimated parameter by its own name (as cierva's aircraft declares them), and a model's
    /// declared parameters as they are. A model refuses a name it does not declare.
    pub fn as_declared(&self) -> BTreeMap<String, f64> {
        self.named()
            .into_iter()
            .filter_map(|(n, v)| Some((format!("corrections.{n}"), v?)))
            .chain(self.estimated.iter().map(|(n, v)| (n.clone(), *v)))
            .chain(self.parameters.iter().map(|(n, v)| (n.clone(), *v)))
            .collect()
    }

    /// The correction `name` (as written), where the set gives it.
    pub fn get_named(&self, name: &str) -> Option<f64> {
        self.named()
            .into_iter()
            .find(|(n, _)| *n == name)
            .and_then(|(_, v)| v)
    }

    /// Sets the correction `name` (as written); `None` for a name that is no correction.
    pub fn set_named(&mut self, name: &str, value: f64) -> Option<()> {
        let slot = match name {
            "propeller_blockage" => &mut self.propeller_blockage,
            "hub_aoa_factor" => &mut self.hub_aoa_factor,
            "profile_drag_scale" => &mut self.profile_drag_scale,
            "profile_drag_increment" => &mut self.profile_drag_increment,
            "pitch_offset_deg" => &mut self.pitch_offset_deg,
            "lateral_inflow_offset_m_s" => &mut self.lateral_inflow_offset_m_s,
            "elastic_twist_deg_per_kpa" => &mut self.elastic_twist_deg_per_kpa,
            "hub_drag_area_m2" => &mut self.hub_drag_area_m2,
            "profile_drag_reynolds_exponent" => &mut self.profile_drag_reynolds_exponent,
            _ => return None,
        };
        *slot = Some(value);
        Some(())
    }

    /// Every correction by its name as written, with its value where the set gives it.
    fn named(&self) -> [(&'static str, Option<f64>); 9] {
        [
            ("propeller_blockage", self.propeller_blockage),
            ("hub_aoa_factor", self.hub_aoa_factor),
            ("profile_drag_scale", self.profile_drag_scale),
            ("profile_drag_increment", self.profile_drag_increment),
            ("pitch_offset_deg", self.pitch_offset_deg),
            ("lateral_inflow_offset_m_s", self.lateral_inflow_offset_m_s),
            ("elastic_twist_deg_per_kpa", self.elastic_twist_deg_per_kpa),
            ("hub_drag_area_m2", self.hub_drag_area_m2),
            (
                "profile_drag_reynolds_exponent",
                self.profile_drag_reynolds_exponent,
            ),
        ]
    }

    /// The corrections given, as `name=value` pairs (for labels and cache keys).
    pub fn describe(&self) -> String {
        let all = self.named();
        let given: Vec<String> = all
            .iter()
            .filter_map(|(n, v)| v.map(|v| format!("{n}={v}")))
            .chain(self.estimated.iter().map(|(n, v)| format!("{n}={v}")))
            .chain(self.parameters.iter().map(|(n, v)| format!("{n}={v}")))
            .collect();
        if given.is_empty() {
            "none".into()
        } else {
            given.join(",")
        }
    }

    /// Sets the blade corrections on a rotor; an aircraft correction is an error.
    pub fn apply_to_rotor(&self, r: &mut Rotor) -> Result<(), String> {
        self.no_declared_parameters()?;
        if self.needs_aircraft() {
            return Err(
                "propeller_blockage, hub_aoa_factor and estimated physical parameters correct an aircraft, not an isolated rotor"
                    .into(),
            );
        }
        let c = &mut r.corrections;
        if let Some(v) = self.profile_drag_scale {
            c.profile_drag_scale = v;
        }
        if let Some(v) = self.profile_drag_increment {
            c.profile_drag_increment = v;
        }
        if let Some(v) = self.pitch_offset_deg {
            c.pitch_offset_rad = v.to_radians();
        }
        if let Some(v) = self.lateral_inflow_offset_m_s {
            c.lateral_inflow_offset_m_s = v;
        }
        if let Some(v) = self.elastic_twist_deg_per_kpa {
            c.elastic_twist_rad_per_pa = v.to_radians() / 1000.0;
        }
        if let Some(v) = self.hub_drag_area_m2 {
            r.hub_drag_area_m2 = v;
        }
        if let Some(v) = self.profile_drag_reynolds_exponent {
            c.profile_drag_reynolds_exponent = v;
        }
        r.validate().map_err(|e| e.to_string())
    }

    /// An error where the set carries a model's declared parameters: those go with every
    /// request to the model that declares them, not onto a file of cierva's.
    fn no_declared_parameters(&self) -> Result<(), String> {
        match self.parameters.keys().next() {
            Some(name) => Err(format!(
                "`{name}` is a model's declared parameter: it is sent to the model behind the model interface, not set on an aircraft or rotor file"
            )),
            None => Ok(()),
        }
    }

    /// Sets every given correction on an aircraft (blade corrections on its main rotor).
    pub fn apply_to_aircraft(&self, a: &mut Aircraft) -> Result<(), String> {
        self.no_declared_parameters()?;
        if let Some(b) = self.propeller_blockage {
            a.propeller.propeller.blockage = b;
        }
        if let Some(k) = self.hub_aoa_factor {
            a.hub_aoa_factor = Some(k);
        }
        for (name, v) in &self.estimated {
            crate::inputs::parameters::set_parameter(a, name, *v)
                .ok_or_else(|| format!("`{name}` is not a physical parameter this aircraft has"))?;
        }
        let blade = CorrectionSet {
            propeller_blockage: None,
            hub_aoa_factor: None,
            estimated: BTreeMap::new(),
            ..self.clone()
        };
        blade.apply_to_rotor(&mut a.main_rotor.rotor)?;
        a.validate().map_err(|e| e.to_string())
    }
}

/// What a corrections file corrects: exactly one of an aircraft file's id, a rotor file's id,
/// or a model behind the model interface as its cases write it.
#[derive(Debug, Clone, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AppliesTo {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aircraft: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotor: Option<String>,
    /// A model behind the model interface, as its cases write it (`command: ...`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
}

/// A corrections file as written (and as `cierva fit` writes it).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CorrectionsFileSpec {
    pub id: String,
    pub title: String,
    pub applies_to: AppliesTo,
    pub corrections: CorrectionSet,
    pub provenance: Provenance,
    /// The fit that produced it, for people to read (not used by `validate`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<serde_json::Value>,
    /// What the fit predicts for data it did not see (`cierva fit`'s cross-validation,
    /// [`crate::uncertainty::calibration::summary`]): per quantity and regime, the RMS relative
    /// error held out, the uncorrected model's on the same data, the model-discrepancy term, and
    /// the regimes it makes worse.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cross_validation: Option<serde_json::Value>,
    /// Checks the corrections are not applied to by default: the regimes where, held out, they
    /// predict worse than the uncorrected model (`cierva fit` writes them from its
    /// cross-validation). Delete an entry to apply the corrections there anyway.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_applied_to: Vec<NotApplied>,
    /// Where the corrections were fitted: the span of their targets' conditions (`cierva fit`
    /// and `cierva retune` write it). A check outside it is run with them, and labelled an
    /// extrapolation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub domain: Option<Domain>,
    /// The checks the fit was fitted to, by case (`cierva fit` writes them from its targets):
    /// with the corrections applied, such a check is `calibrated_on` the file, its verdict
    /// reported apart and never counted as validation evidence.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub calibrated_on: BTreeMap<String, Vec<String>>,
    /// The fitted parameters' joint distribution (`cierva fit` writes it): what an
    /// uncertainty study with the corrections applied samples them from, instead of their
    /// prior ranges.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub posterior: Option<Posterior>,
}

/// A fit's parameters' joint distribution about its estimate: a normal of covariance
/// `(J'WJ / b^2 + P)^-1`, where `J'WJ` is the targets' information at the end (each target
/// weighted by its standard error), `b` the Birge factor its standard errors were scaled by
/// and `P` each parameter's bounds as a normal of the same variance (a uniform's,
/// `width^2 / 12`). The bounds' term keeps it finite where the targets do not see a direction
/// (more parameters than targets); where they do, it is small. Drawn values outside the bounds
/// are reflected into them (so an estimate on a bound gets a half-normal). A Laplace
/// approximation of the posterior under a uniform prior over the bounds, not the posterior:
/// its shape far from the estimate is the normal's.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Posterior {
    /// How it was made, in words.
    pub method: String,
    /// Each fitted parameter by the name its model takes it under, in the covariance's order.
    pub parameters: Vec<PosteriorParameter>,
    /// The covariance, a row per parameter.
    pub covariance: Vec<Vec<f64>>,
}

/// A fitted parameter in a [`Posterior`]: its name as the model takes it
/// (`corrections.pitch_offset_deg`, `airframe.fin.area_m2`), its fitted value and its bounds.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PosteriorParameter {
    pub name: String,
    pub value: f64,
    pub lower: f64,
    pub upper: f64,
}

impl Posterior {
    /// Where it is not a distribution: a field and what is wrong with it.
    pub fn problem(&self) -> Option<(String, String)> {
        let n = self.parameters.len();
        for (i, p) in self.parameters.iter().enumerate() {
            let ok = [p.value, p.lower, p.upper].iter().all(|v| v.is_finite())
                && p.lower < p.upper
                && (p.lower..=p.upper).contains(&p.value);
            if !ok {
                return Some((
                    format!("posterior.parameters[{i}]"),
                    format!(
                        "`{}`: its value {} must lie in finite bounds [{}, {}] that are not empty",
                        p.name, p.value, p.lower, p.upper
                    ),
                ));
            }
        }
        if self.covariance.len() != n || self.covariance.iter().any(|r| r.len() != n) {
            return Some((
                "posterior.covariance".into(),
                format!("must be {n} rows of {n} numbers, one per parameter"),
            ));
        }
        let m = nalgebra::DMatrix::from_fn(n, n, |a, b| self.covariance[a][b]);
        let symmetric = (0..n).all(|a| {
            (0..n).all(|b| {
                (m[(a, b)] - m[(b, a)]).abs() <= 1e-9 * m[(a, a)].abs().max(m[(b, b)].abs())
            })
        });
        if !m.iter().all(|v| v.is_finite()) || !symmetric || m.clone().cholesky().is_none() {
            return Some((
                "posterior.covariance".into(),
                "must be a symmetric, positive definite matrix of finite numbers".into(),
            ));
        }
        None
    }
}

/// The span of the conditions a corrections file was fitted on, each `[lowest, highest]` over
/// its targets where they state it. A check outside any stated span is an extrapolation of the
/// corrections ([`Domain::outside`]); a span the targets do not state says nothing.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// A tunnel's tip-speed ratio (TR 515's rows).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_speed_ratio: Option<[f64; 2]>,
    /// A tunnel's airspeed, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tunnel_airspeed_m_s: Option<[f64; 2]>,
    /// A flight condition's airspeed, mph.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub airspeed_mph: Option<[f64; 2]>,
    /// A flight condition's mass, kg (where the targets state one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<[f64; 2]>,
}

/// How far past a domain's end a condition may lie and still be inside, relative: the
/// rounding of a written condition (a tip-speed ratio to three decimals, a speed converted from
/// knots).
pub const DOMAIN_ROUNDING: f64 = 1e-6;

impl Domain {
    /// The span of `values` (finite ones), `None` without any.
    pub fn span(values: impl Iterator<Item = f64>) -> Option<[f64; 2]> {
        values
            .filter(|v| v.is_finite())
            .fold(None, |s: Option<[f64; 2]>, v| match s {
                None => Some([v, v]),
                Some([lo, hi]) => Some([lo.min(v), hi.max(v)]),
            })
    }

    /// Why a condition lies outside the domain (each stated quantity outside its span, in
    /// words), or `None` inside: a tunnel's tip-speed ratio and airspeed, or a flight's
    /// airspeed and mass, whichever the condition states.
    pub fn outside(
        &self,
        tunnel: Option<&crate::inputs::condition::TunnelSpec>,
        flight: Option<(f64, Option<f64>)>,
    ) -> Option<String> {
        let mut why = Vec::new();
        let mut judge = |name: &str, unit: &str, value: Option<f64>, span: Option<[f64; 2]>| {
            if let (Some(v), Some([lo, hi])) = (value, span) {
                let slack = DOMAIN_ROUNDING * lo.abs().max(hi.abs());
                if v < lo - slack || v > hi + slack {
                    why.push(format!("{name} {v}{unit} outside [{lo}, {hi}]{unit}"));
                }
            }
        };
        if let Some(t) = tunnel {
            judge(
                "tip-speed ratio",
                "",
                t.tip_speed_ratio,
                self.tip_speed_ratio,
            );
            judge(
                "tunnel airspeed",
                " m/s",
                t.airspeed_m_s,
                self.tunnel_airspeed_m_s,
            );
        }
        if let Some((airspeed_mph, mass_kg)) = flight {
            judge("airspeed", " mph", Some(airspeed_mph), self.airspeed_mph);
            judge("mass", " kg", mass_kg, self.mass_kg);
        }
        (!why.is_empty()).then(|| why.join(", "))
    }
}

/// A regime of a case's checks that a corrections file is not applied to, and why.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NotApplied {
    /// The case's id.
    pub case: String,
    /// The regime's name (the fit file's `cross_validation.regimes`).
    pub regime: String,
    /// The case's checks in the regime.
    pub checks: Vec<String>,
    /// Why: the held-out errors, calibrated and uncorrected.
    pub reason: String,
}

/// A calibration's stated predictive error, from its file's `cross_validation` (`cierva fit`,
/// [`crate::uncertainty::calibration::summary`]): the model-discrepancy term (the relative
/// spread of held-out errors beyond the data's scatter) per quantity, pooled over every held-out
/// target and per regime. A prediction made with the corrections carries it
/// ([`crate::uncertainty::propagate`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PredictiveError {
    /// Per quantity, over every held-out target.
    pub pooled: BTreeMap<String, f64>,
    pub regimes: Vec<RegimeError>,
}

/// One regime's predictive error and the checks it covers.
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
pub struct RegimeError {
    #[serde(skip)]
    pub name: String,
    /// The regime's checks by case id (written by `cierva fit` since the regimes carried
    /// their checks; an older file's regimes cover none).
    #[serde(default)]
    pub checks: BTreeMap<String, Vec<String>>,
    #[serde(default, rename = "discrepancy_relative_sd")]
    pub relative_sd: BTreeMap<String, f64>,
}

/// The part of a file's `cross_validation` a prediction reads.
#[derive(Debug, Deserialize)]
struct PredictiveErrorSpec {
    #[serde(default)]
    discrepancy_relative_sd: BTreeMap<String, f64>,
    #[serde(default)]
    regimes: BTreeMap<String, RegimeError>,
}

/// Quantities whose relative errors are one another's (a rotor speed in rad/s or rpm).
const SAME_RELATIVE_ERROR: &[(&str, &str)] = &[("rotor_omega_rad_s", "rotor_rpm")];

impl PredictiveError {
    /// The relative standard deviation a prediction of `quantity` at `check` of case `case`
    /// carries, and where it comes from: the regime that holds the check, else the pooled
    /// figure (the check is in none of the calibration's regimes: a condition its
    /// cross-validation never saw). `None` where the calibration states nothing for the
    /// quantity.
    pub fn relative_sd(&self, case: &str, check: &str, quantity: &str) -> Option<(f64, String)> {
        let named = |m: &BTreeMap<String, f64>| {
            m.get(quantity).copied().or_else(|| {
                SAME_RELATIVE_ERROR
                    .iter()
                    .find_map(|(a, b)| match quantity {
                        q if q == *a => m.get(*b).copied(),
                        q if q == *b => m.get(*a).copied(),
                        _ => None,
                    })
            })
        };
        let regime = self.regimes.iter().find(|r| {
            r.checks
                .get(case)
                .is_some_and(|c| c.iter().any(|c| c == check))
        });
        match regime {
            Some(r) => named(&r.relative_sd).map(|v| (v, format!("regime `{}`", r.name))),
            None => named(&self.pooled).map(|v| {
                (
                    v,
                    "pooled over its held-out targets (this check is in none of its regimes)"
                        .to_string(),
                )
            }),
        }
        .filter(|(v, _)| v.is_finite())
    }
}

/// What a loaded corrections file corrects.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Corrects {
    Aircraft(String),
    Rotor(String),
    /// A model behind the model interface, as its cases write it.
    Model(String),
}

impl From<&Corrects> for AppliesTo {
    /// What a corrections file writes for what it corrects.
    fn from(c: &Corrects) -> Self {
        match c {
            Corrects::Aircraft(a) => AppliesTo {
                aircraft: Some(a.clone()),
                ..AppliesTo::default()
            },
            Corrects::Rotor(r) => AppliesTo {
                rotor: Some(r.clone()),
                ..AppliesTo::default()
            },
            Corrects::Model(m) => AppliesTo {
                model: Some(m.clone()),
                ..AppliesTo::default()
            },
        }
    }
}

/// A loaded, checked corrections file.
#[derive(Debug, Clone, PartialEq)]
pub struct CorrectionsFile {
    pub path: PathBuf,
    pub id: String,
    pub target: Corrects,
    pub corrections: CorrectionSet,
    /// The checks it is not applied to by default (see [`CorrectionsFileSpec::not_applied_to`]).
    pub not_applied_to: Vec<NotApplied>,
    /// Its stated predictive error, if its fit was cross-validated.
    pub predictive_error: Option<PredictiveError>,
    /// Where it was fitted ([`CorrectionsFileSpec::domain`]), where it says.
    pub domain: Option<Domain>,
    /// The checks it was fitted to, by case ([`CorrectionsFileSpec::calibrated_on`]).
    pub calibrated_on: BTreeMap<String, Vec<String>>,
    /// Its fitted parameters' joint distribution ([`CorrectionsFileSpec::posterior`]).
    pub posterior: Option<Posterior>,
}

impl CorrectionsFile {
    /// Where applying the file to a subject fails (`apply` applies a set to it): the
    /// correction that fails alone (`corrections.hub_aoa_factor`: the file, its line and
    /// column, and why), or `None` where none does alone.
    pub fn locate(
        &self,
        apply: impl Fn(&CorrectionSet) -> Result<(), String>,
    ) -> Option<InputError> {
        for (name, value) in self.corrections.named() {
            let Some(v) = value else { continue };
            let mut one = CorrectionSet::default();
            if one.set_named(name, v).is_some()
                && let Err(e) = apply(&one)
                && let Ok(src) = yaml::read(&self.path)
            {
                return Some(InputError::field(
                    &self.path,
                    &src,
                    &format!("corrections.{name}"),
                    e,
                ));
            }
        }
        for (name, v) in &self.corrections.estimated {
            let one = CorrectionSet {
                estimated: [(name.clone(), *v)].into_iter().collect(),
                ..Default::default()
            };
            if let Err(e) = apply(&one)
                && let Ok(src) = yaml::read(&self.path)
            {
                return Some(InputError::field(
                    &self.path,
                    &src,
                    &format!("corrections.estimated.{name}"),
                    e,
                ));
            }
        }
        None
    }
}

/// What a corrections file corrects, from its `applies_to`, where its corrections suit it: a
/// model behind the model interface takes declared parameters only, an aircraft or a rotor
/// file none, and a rotor no aircraft correction. An error is its field and message.
fn target_of(spec: &CorrectionsFileSpec) -> Result<Corrects, (&'static str, String)> {
    let declared_only = CorrectionSet {
        parameters: BTreeMap::new(),
        ..spec.corrections.clone()
    } == CorrectionSet::default();
    let a = &spec.applies_to;
    match (&a.aircraft, &a.rotor, &a.model) {
        (None, None, Some(m)) => {
            if !declared_only {
                return Err((
                    "corrections",
                    "a model behind the model interface takes its declared parameters only: put them under `corrections.parameters` by the names the model declares".into(),
                ));
            }
            Ok(Corrects::Model(m.clone()))
        }
        (_, _, None) if !spec.corrections.parameters.is_empty() => {
            Err((
                "corrections.parameters",
                "declared parameters go to a model behind the model interface: say `applies_to: {model: ...}` (an aircraft or rotor file takes its corrections and `estimated` by their own names)".into(),
            ))
        }
        (Some(a), None, None) => Ok(Corrects::Aircraft(a.clone())),
        (None, Some(r), None) => {
            if spec.corrections.needs_aircraft() {
                return Err((
                    "corrections",
                    "propeller_blockage, hub_aoa_factor and estimated physical parameters correct an aircraft: apply them to `aircraft`, not `rotor`".into(),
                ));
            }
            Ok(Corrects::Rotor(r.clone()))
        }
        _ => {
            Err((
                "applies_to",
                "give exactly one of `aircraft` or `rotor` (the id of the file to correct) or `model` (a model behind the model interface, as its cases write it)".into(),
            ))
        }
    }
}

/// Loads and checks a corrections file.
pub fn load(path: &Path) -> Result<CorrectionsFile, InputError> {
    let src = yaml::read(path)?;
    let spec: CorrectionsFileSpec = yaml::parse(path, &src)?;
    let err = |field: &str, m: String| InputError::field(path, &src, field, m);
    crate::inputs::reference::check_id(path, &src, &spec.id)?;
    let target = target_of(&spec).map_err(|(field, m)| err(field, m))?;
    let c = &spec.corrections;
    for (name, v) in c.named() {
        if let Some(v) = v
            && !v.is_finite()
        {
            return Err(err(
                &format!("corrections.{name}"),
                format!("must be a finite number, not {v}"),
            ));
        }
    }
    let names = crate::inputs::parameters::physical_names();
    for (name, v) in &c.estimated {
        let field = format!("corrections.estimated.{name}");
        if !names.contains(name) {
            let hint = yaml::nearest(name, &names)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(err(
                "corrections.estimated",
                format!("`{name}` is not a physical parameter{hint}"),
            ));
        }
        if !v.is_finite() {
            return Err(err(&field, format!("must be a finite number, not {v}")));
        }
    }
    for (name, v) in &c.parameters {
        if !v.is_finite() {
            return Err(err(
                &format!("corrections.parameters.{name}"),
                format!("must be a finite number, not {v}"),
            ));
        }
    }
    for (i, n) in spec.not_applied_to.iter().enumerate() {
        let here = format!("not_applied_to[{i}]");
        if n.case.trim().is_empty() || n.checks.is_empty() {
            return Err(err(
                &here,
                "name the case and at least one of its checks".into(),
            ));
        }
        if n.reason.trim().is_empty() {
            return Err(err(
                &format!("{here}.reason"),
                "say why the corrections are not applied there".into(),
            ));
        }
    }
    if let Some((field, m)) = spec.posterior.as_ref().and_then(Posterior::problem) {
        return Err(err(&field, m));
    }
    let predictive_error = match &spec.cross_validation {
        None => None,
        Some(v) => {
            let p: PredictiveErrorSpec = serde_json::from_value(v.clone())
                .map_err(|e| err("cross_validation", e.to_string()))?;
            let bad = p
                .discrepancy_relative_sd
                .iter()
                .chain(p.regimes.values().flat_map(|r| &r.relative_sd))
                .find(|(_, v)| !v.is_finite() || **v < 0.0);
            if let Some((q, v)) = bad {
                return Err(err(
                    "cross_validation",
                    format!("the discrepancy of `{q}` must be a finite number >= 0, not {v}"),
                ));
            }
            Some(PredictiveError {
                pooled: p.discrepancy_relative_sd,
                regimes: p
                    .regimes
                    .into_iter()
                    .map(|(name, r)| RegimeError { name, ..r })
                    .collect(),
            })
        }
    };
    Ok(CorrectionsFile {
        path: path.to_path_buf(),
        id: spec.id,
        target,
        corrections: spec.corrections,
        not_applied_to: spec.not_applied_to,
        predictive_error,
        domain: spec.domain,
        calibrated_on: spec.calibrated_on,
        posterior: spec.posterior,
    })
}
