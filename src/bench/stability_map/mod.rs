//! The dt x ks sweep behind `tetrasim stability` and its heat maps: short runs of every
//! method over a grid of steps and stiffnesses (through [`crate::runner::run`]), judged
//! against the stable-step estimate of [`crate::stability`].

pub mod plot;
pub mod sweep;
