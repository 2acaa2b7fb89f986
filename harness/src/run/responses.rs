//! A flight model's frequency responses: every state to every control at a set of
//! frequencies, from a linear model's A and B or (cierva's aircraft with a teetering rotor)
//! from its linearisation with the rotor's flapping states by harmonic balance. What a
//! `frequency_response` check, a fit's response targets and a retune compare with records.

use rustfft::num_complex::Complex64 as C;

/// `e_output (i omega I - A)^-1 B e_input` of a linear model at each frequency, Hz.
pub fn linear_response(
    model: &cierva_model::LinearModel,
    output: usize,
    input: usize,
    frequencies_hz: &[f64],
) -> Result<Vec<C>, String> {
    use nalgebra::{Complex, DMatrix};
    let n = model.states().len();
    frequencies_hz
        .iter()
        .map(|f| {
            let w = 2.0 * std::f64::consts::PI * f;
            let m = DMatrix::from_fn(n, n, |i, j| {
                Complex::new(-model.a()[(i, j)], if i == j { w } else { 0.0 })
            });
            let b = DMatrix::from_fn(n, 1, |i, _| Complex::new(model.b()[(i, input)], 0.0));
            let x = m
                .lu()
                .solve(&b)
                .ok_or_else(|| format!("i omega I - A is singular at {f} Hz"))?;
            Ok(C::new(x[output].re, x[output].im))
        })
        .collect()
}

/// A flight model's frequency responses at one flight condition: every state to every control
/// at each frequency, from one linearisation (a model's A and B; for cierva's aircraft with a
/// teetering hub, the linearisation with the rotor's flapping states and its baseband response
/// by harmonic balance, [`aircraft_responses`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Responses {
    pub states: Vec<String>,
    pub controls: Vec<String>,
    pub frequencies_hz: Vec<f64>,
    /// States x controls at each frequency.
    pub at: Vec<nalgebra::DMatrix<C>>,
    /// Which model gave them, in words.
    pub from: String,
}

impl Responses {
    /// The response of `output` to `input` at one of the frequencies.
    pub fn at(&self, input: &str, output: &str, frequency_hz: f64) -> Result<C, String> {
        let o = self
            .states
            .iter()
            .position(|s| s == output)
            .ok_or_else(|| format!("`{output}` is not a state of the model"))?;
        let i = self
            .controls
            .iter()
            .position(|s| s == input)
            .ok_or_else(|| format!("`{input}` is not a control of the model"))?;
        let k = self
            .frequencies_hz
            .iter()
            .position(|f| *f == frequency_hz)
            .ok_or_else(|| format!("no response computed at {frequency_hz} Hz"))?;
        Ok(self.at[k][(o, i)])
    }

    /// The response of `output` to `input` as a record measures it when the record's other
    /// controls moved with `input`: `H = G_input + sum_j G_j T_j`, `T_j` each other control's
    /// measured transfer from `input` (its cross-spectrum with `input` over `input`'s
    /// autospectrum, [`crate::fit::retune::responses`]).
    ///
    /// Why: a single-input estimate `G_y,input / G_input,input` of a linear aircraft is
    /// `sum_j G_j G_j,input / G_input,input` exactly, whoever moved the other controls (a pilot
    /// holding the other axes, here); disturbances the input does not cause (turbulence, the
    /// pilot's own drift) average out of the cross-spectra. So the model's response compares
    /// with the record's only with the record's own control activity added, and no conditioning
    /// on controls that are fed back (which the disturbances bias) is needed.
    pub fn as_flown(
        &self,
        input: &str,
        output: &str,
        frequency_hz: f64,
        others: &[(String, C)],
    ) -> Result<C, String> {
        let mut h = self.at(input, output, frequency_hz)?;
        for (control, t) in others {
            h += self.at(control, output, frequency_hz)? * t;
        }
        Ok(h)
    }

    /// Which model gave the responses, in words.
    pub fn model(&self) -> &str {
        &self.from
    }

    /// Every state's response to every control of a linear model's `A` and `B`
    /// ([`linear_response`]) at each frequency; `from` says which model it is, in words.
    pub fn of_linear_model(
        model: &cierva_model::LinearModel,
        frequencies_hz: &[f64],
        from: String,
    ) -> Result<Self, String> {
        use nalgebra::DMatrix;
        let (ns, nc) = (model.states().len(), model.controls().len());
        let mut at = vec![DMatrix::from_element(ns, nc, C::new(0.0, 0.0)); frequencies_hz.len()];
        for i in 0..nc {
            for o in 0..ns {
                let h = linear_response(model, o, i, frequencies_hz)?;
                for (m, v) in at.iter_mut().zip(h) {
                    m[(o, i)] = v;
                }
            }
        }
        Ok(Self {
            states: model.states().to_vec(),
            controls: model.controls().to_vec(),
            frequencies_hz: frequencies_hz.to_vec(),
            at,
            from,
        })
    }
}

/// What a model's responses from its own `A` and `B` are, in words (a model behind the model
/// interface, described).
pub fn from_a_and_b(model: &str) -> String {
    format!("the A and B {model} gives")
}

/// What an aircraft's responses with its rotor's flapping states are, in words.
pub const WITH_FLAPPING: &str =
    "the linearisation with the rotor's flapping states, baseband response by harmonic balance";
/// What an aircraft's quasi-static responses are, in words.
pub const QUASI_STATIC: &str =
    "the quasi-static linearisation (no flapping linearisation for this rotor's hub)";

/// An aircraft's responses ([`Responses`]) at its trim `trim` for `loading`: with its rotor's
/// flapping states for a teetering hub (baseband, by harmonic balance), from its quasi-static
/// linearisation there otherwise (`quasi_static`, asked only then).
pub fn aircraft_responses(
    aircraft: &cierva_model::aircraft::Aircraft,
    loading: crate::inputs::condition::Loading,
    trim: &cierva_model::aircraft::trim::Trim,
    quasi_static: impl FnOnce() -> Result<cierva_model::LinearModel, String>,
    frequencies_hz: &[f64],
) -> Result<Responses, String> {
    use nalgebra::{Complex, DMatrix};
    let teetering =
        aircraft.main_rotor.rotor.hub == cierva_model::components::rotor::Hub::Teetering;
    let to_c = |h: &DMatrix<Complex<f64>>, n: usize| {
        DMatrix::from_fn(n, h.ncols(), |r, c| C::new(h[(r, c)].re, h[(r, c)].im))
    };
    if teetering {
        let wf = crate::run::linearise::run_linearise_with_flapping(aircraft, trim, loading)?;
        // The flapping, inflow and propeller states are the model's own: the records measure
        // the rigid body's (the first rows).
        let n = cierva_model::aircraft::linearise::STATES.len();
        let at = frequencies_hz
            .iter()
            .map(|f| {
                wf.baseband_response(2.0 * std::f64::consts::PI * f)
                    .map(|h| to_c(&h, n))
                    .map_err(|e| format!("the baseband response at {f} Hz: {e}"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Responses {
            states: wf.model.states()[..n].to_vec(),
            controls: wf.model.controls().to_vec(),
            frequencies_hz: frequencies_hz.to_vec(),
            at,
            from: WITH_FLAPPING.into(),
        })
    } else {
        Responses::of_linear_model(&quasi_static()?, frequencies_hz, QUASI_STATIC.into())
    }
}
