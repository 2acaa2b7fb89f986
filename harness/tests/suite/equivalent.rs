//! An identification of a model's own response gives the model back (moved from
//! `ident/equivalent.rs`, whose unit tests never ran: the library builds no tests of its own).

use cierva_harness::ident::equivalent::{
    Response, identify_in_band, identify_with_records, lti_response,
};
use cierva_harness::ident::{ConfigSpec, Identification};
use cierva_model::LinearModel;

/// `found` has `count` derivatives, each the model's own to 1e-9.
fn assert_identified_as_itself(found: &Identification, model: &LinearModel, count: usize) {
    assert_eq!(found.derivatives.len(), count);
    for d in &found.derivatives {
        let want = model.derivative_value(&d.name).unwrap();
        assert!(
            (d.estimate - want).abs() < 1e-9 * (1.0 + want.abs()),
            "{}: {} against {want}",
            d.name,
            d.estimate
        );
    }
}

/// A model of the set-up's own form is identified as itself from its frequency response
/// (no noise, an exact structure): every derivative within 1e-9 of its own value.
#[test]
fn a_model_of_the_set_ups_form_is_identified_as_itself() {
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let a = vec![
        vec![-0.13, 0.17, -0.7, -9.8, -0.04],
        vec![-0.17, -1.1, 31.0, -0.5, -0.29],
        vec![0.015, -0.086, -1.13, 0.0, -0.003],
        vec![0.0, 0.0, 1.0, 0.0, 0.0],
        vec![0.23, 1.16, -3.2, 0.0, -0.19],
    ];
    let b = vec![
        vec![-0.05],
        vec![-0.10],
        vec![0.041],
        vec![0.0],
        vec![0.126],
    ];
    let model = LinearModel::from_rows(
        names(&["u", "w", "q", "theta", "Omega"]),
        names(&["eta_s"]),
        &a,
        &b,
    )
    .unwrap();
    let config = ConfigSpec::for_model(cierva_harness::ident::Setup::Longitudinal);
    let found = identify_in_band(&config, &model).unwrap();
    assert_identified_as_itself(&found, &model, 4 * 6);
}

/// The same model is identified as itself from its response to a record's controls (a
/// sweep on the stick, a slow pedal): the record's own transforms weight the fit, and the
/// equations hold at every point, so the derivatives come back to 1e-9.
#[test]
fn a_model_is_identified_as_itself_from_a_record_s_controls() {
    use cierva_harness::inputs::record::{Record, RecordMeta, Sensors};
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let model = LinearModel::from_rows(
        names(&["u", "w", "q", "theta", "Omega"]),
        names(&["eta_s", "eta_p"]),
        &[
            vec![-0.13, 0.17, -0.7, -9.8, -0.04],
            vec![-0.17, -1.1, 31.0, -0.5, -0.29],
            vec![0.015, -0.086, -1.13, 0.0, -0.003],
            vec![0.0, 0.0, 1.0, 0.0, 0.0],
            vec![0.23, 1.16, -3.2, 0.0, -0.19],
        ],
        &[
            vec![-0.05, 0.001],
            vec![-0.10, 0.0],
            vec![0.041, 0.002],
            vec![0.0, 0.0],
            vec![0.126, 0.0],
        ],
    )
    .unwrap();
    let (n, dt) = (6000, 0.01);
    let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let sweep: Vec<f64> = t
        .iter()
        .map(|t| 50.0 + 3.0 * (2.0 * std::f64::consts::PI * (0.05 + 0.03 * t) * t).sin())
        .collect();
    let pedal: Vec<f64> = t.iter().map(|t| 50.0 + (1.3 * t).sin()).collect();
    let constant = |v: f64| vec![v; n];
    let channels = names(&cierva_harness::inputs::record::REQUIRED)
        .into_iter()
        .chain(names(&["eta_s_percent", "eta_p_percent"]))
        .collect();
    let mut data = vec![t.clone()];
    data.extend([30.0, 0.05, 0.0, 0.0, 0.0, 0.0, 0.0, 0.05, 40.0].map(constant));
    data.extend([sweep, pedal]);
    let record = Record {
        path: "sweep.csv".into(),
        meta: RecordMeta {
            id: "sweep".into(),
            title: "t".into(),
            provenance: cierva_harness::inputs::reference::Provenance {
                source: "test".into(),
                notes: None,
            },
            synthetic: None,
            aircraft: "test".into(),
            sample_rate_hz: 1.0 / dt,
            sensors: Some(Sensors {
                probe_position_m: [0.0; 3],
                cg_position_m: [0.0; 3],
            }),
            condition: Default::default(),
            trim: [("eta_s_percent", 50.0), ("eta_p_percent", 50.0)]
                .map(|(k, v)| (k.to_string(), v))
                .into_iter()
                .collect(),
            controls: names(&["eta_s_percent", "eta_p_percent"]),
            channels: Default::default(),
            travel: Default::default(),
            excitation: Default::default(),
        },
        channels,
        data,
        notes: Vec::new(),
    };
    let mut config = ConfigSpec::longitudinal(&record);
    config
        .controls
        .insert("eta_p".to_string(), "eta_p_percent".to_string());
    let at = lti_response(&model);
    let found = identify_with_records(
        std::slice::from_ref(&record),
        &config,
        Response {
            states: model.states(),
            controls: model.controls(),
            at: &at,
        },
    )
    .unwrap();
    assert_identified_as_itself(&found, &model, 4 * 7);
}
