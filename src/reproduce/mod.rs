//! The paper pipeline as a library (under construction): what the paper
//! publishes and the reference values its printed numbers encode.

pub mod pipeline;
pub mod reconstruction;
pub mod reference;
pub mod specs;
