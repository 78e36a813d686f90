//! A request's options: the strategy, the words' style, the bounds on its work and words, and
//! what a refusal offers; as a request gives them and as they are checked.
//!
//! Owns: the options' defaults, spellings and ranges (fields named `/options/...`). Must not:
//! decide anything with them.

use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::engine::decision::Style;
use crate::engine::input::{Invalid, RequestLimits, Spelled, ranged};

/// Defaults of the options that bound a request's work and words.
pub const DEFAULT_MAX_SPOKEN: usize = 5;
pub const DEFAULT_MAX_READINGS: usize = 10_000;
/// The most readings a request may ask to be read (`options.max_readings`).
pub const MOST_READINGS: usize = 100_000;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// The paper's algorithm: simulate first, then ask only about what may be done.
    #[default]
    Moral,
    /// The status quo the paper argues against: ask about every candidate before moral reasoning.
    Reflexive,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SinglePermissible {
    #[default]
    Assume,
    Confirm,
}

/// Whether soft norms rank the readings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SoftNorms {
    /// Among the acceptable readings only those with the highest norm score are kept.
    #[default]
    Rank,
    /// Soft norms are not checked: an experiment's control condition.
    Ignore,
}

impl Spelled for SoftNorms {
    const ALL: &'static [SoftNorms] = &[SoftNorms::Rank, SoftNorms::Ignore];

    fn as_str(self) -> &'static str {
        match self {
            SoftNorms::Rank => "rank",
            SoftNorms::Ignore => "ignore",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub strategy: Strategy,
    pub single_permissible: SinglePermissible,
    pub style: Style,
    /// Most readings a question names; above it the question names the few likeliest and ends
    /// "or something else", or names the ambiguous words.
    pub max_spoken: usize,
    /// Most readings simulated; above it nothing is simulated and the ambiguous words are named.
    pub max_readings: usize,
    /// When exactly one reading is acceptable and the share of the others is above this ratio,
    /// confirm instead of assuming. `None`: always Algorithm 1's assumption.
    pub confirm_above_ratio: Option<f64>,
    pub soft_norms: SoftNorms,
    /// Whether a refusal offers the nearest acceptable reading; `None`: by the style.
    pub alternatives: Option<Alternatives>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            strategy: Strategy::Moral,
            single_permissible: SinglePermissible::Assume,
            style: Style::Diarc,
            max_spoken: DEFAULT_MAX_SPOKEN,
            max_readings: DEFAULT_MAX_READINGS,
            confirm_above_ratio: None,
            soft_norms: SoftNorms::Rank,
            alternatives: None,
        }
    }
}

impl Spelled for Strategy {
    const ALL: &'static [Strategy] = &[Strategy::Moral, Strategy::Reflexive];

    fn as_str(self) -> &'static str {
        match self {
            Strategy::Moral => "moral",
            Strategy::Reflexive => "reflexive",
        }
    }
}

impl Spelled for SinglePermissible {
    const ALL: &'static [SinglePermissible] = &[SinglePermissible::Assume, SinglePermissible::Confirm];

    fn as_str(self) -> &'static str {
        match self {
            SinglePermissible::Assume => "assume",
            SinglePermissible::Confirm => "confirm",
        }
    }
}

/// The options as a request gives them; absent ones take their defaults.
#[derive(Clone, Debug, Default)]
pub struct OptionsInput {
    pub strategy: Option<Strategy>,
    pub single_permissible: Option<SinglePermissible>,
    pub style: Option<Style>,
    pub max_spoken: Option<u64>,
    pub max_readings: Option<u64>,
    pub deadline_ms: Option<u64>,
    pub confirm_above_ratio: Option<f64>,
    pub soft_norms: Option<SoftNorms>,
    pub alternatives: Option<Alternatives>,
}

/// Whether a refusal offers the nearest acceptable reading instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Alternatives {
    Offer,
    Off,
}

impl Spelled for Alternatives {
    const ALL: &'static [Alternatives] = &[Alternatives::Offer, Alternatives::Off];

    fn as_str(self) -> &'static str {
        match self {
            Alternatives::Offer => "offer",
            Alternatives::Off => "off",
        }
    }
}

impl Options {
    /// Whether alternatives are looked for: as asked, else in the natural style only (the
    /// paper's words stay exact), and never under the reflexive strategy.
    pub fn offers_alternatives(&self) -> bool {
        let asked = self.alternatives.unwrap_or(match self.style {
            Style::Diarc => Alternatives::Off,
            Style::Natural => Alternatives::Offer,
        });
        asked == Alternatives::Offer && self.strategy == Strategy::Moral
    }
}

impl Options {
    /// The options and the deadline they ask for; fields named as in the request (`/options/..`).
    pub fn from_input(options: OptionsInput, limits: &RequestLimits) -> Result<(Options, Duration), Invalid> {
        if let Some(ratio) = options.confirm_above_ratio
            && !(ratio.is_finite() && (0.0..1.0).contains(&ratio))
        {
            return Err(Invalid::new(
                "/options/confirm_above_ratio",
                "must be a ratio with 0 ≤ ratio < 1",
            ));
        }
        let deadline = limits.deadline(options.deadline_ms)?;
        let max_spoken = ranged(
            "/options/max_spoken",
            options.max_spoken,
            2..=50,
            DEFAULT_MAX_SPOKEN as u64,
        )?;
        let max_readings = ranged(
            "/options/max_readings",
            options.max_readings,
            1..=MOST_READINGS as u64,
            DEFAULT_MAX_READINGS as u64,
        )?;
        let options = Options {
            strategy: options.strategy.unwrap_or_default(),
            single_permissible: options.single_permissible.unwrap_or_default(),
            style: options.style.unwrap_or_default(),
            max_spoken: max_spoken as usize,
            max_readings: max_readings as usize,
            confirm_above_ratio: options.confirm_above_ratio,
            soft_norms: options.soft_norms.unwrap_or_default(),
            alternatives: options.alternatives,
        };
        Ok((options, deadline))
    }
}
