//! Named arrays in named groups, written as a NetCDF-4 file (HDF5 with
//! groups) by the pure-Rust `netcdf-writer` crate: the layout of ArviZ's
//! InferenceData, which `arviz.from_netcdf(path)` opens in one call.
//!
//! This module knows nothing about what the arrays mean; callers (e.g.
//! `calibration::output`) fill the groups ArviZ expects (`posterior`,
//! `sample_stats`, `log_likelihood`, `observed_data`, `prior`, …) with
//! variables over dimensions such as `chain` and `draw`. Every dimension of a
//! group gets an integer coordinate variable 0..n (as ArviZ writes them), and
//! dimension names are per group, so `draw` may differ between `posterior`
//! and `prior`. Arrays are row-major (the last dimension varies fastest).

use netcdf_writer::{NcAttrValue, NcFileBuilder, NcWriteFormat, NcWriteOptions};

use super::error::{ReportError, Result};

/// One array: its name, the names of its dimensions and its values (row-major).
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    pub name: String,
    /// `(dimension name, length)` in order; the product of lengths is `values.len()`.
    pub dims: Vec<(String, usize)>,
    pub values: Vec<f64>,
}

/// A group of variables with string attributes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Group {
    pub name: String,
    pub variables: Vec<Variable>,
    pub attributes: Vec<(String, String)>,
}

/// The whole file: groups plus root attributes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct InferenceData {
    pub groups: Vec<Group>,
    pub attributes: Vec<(String, String)>,
}

fn nc_err(what: &str) -> impl Fn(netcdf_writer::Error) -> ReportError + '_ {
    move |e| ReportError::invalid("InferenceData", format!("{what}: {e}"))
}

impl InferenceData {
    /// Checks shapes: every variable's values fill its dimensions, and a
    /// dimension name has one length within a group.
    pub fn validate(&self) -> Result<()> {
        for g in &self.groups {
            let mut lengths: Vec<(&str, usize)> = Vec::new();
            for v in &g.variables {
                let n: usize = v.dims.iter().map(|(_, l)| *l).product();
                if n != v.values.len() {
                    return Err(ReportError::invalid(
                        "InferenceData",
                        format!("{}/{}: {} values for dimensions {:?}", g.name, v.name, v.values.len(), v.dims),
                    ));
                }
                for (d, l) in &v.dims {
                    match lengths.iter().find(|(n, _)| n == d) {
                        Some((_, l0)) if l0 != l => {
                            return Err(ReportError::invalid(
                                "InferenceData",
                                format!("{}: dimension {d} has lengths {l0} and {l}", g.name),
                            ))
                        }
                        Some(_) => {}
                        None => lengths.push((d, *l)),
                    }
                }
            }
        }
        Ok(())
    }

    /// The NetCDF-4 bytes.
    pub fn to_netcdf(&self) -> Result<Vec<u8>> {
        self.validate()?;
        let mut b = NcFileBuilder::new();
        for (k, v) in &self.attributes {
            b.add_attribute(k.as_str(), NcAttrValue::Chars(v.clone())).map_err(nc_err("root attribute"))?;
        }
        for g in &self.groups {
            write_group(&mut b, g)?;
        }
        let (_, bytes) = b.to_vec(NcWriteOptions { format: NcWriteFormat::Nc4 }).map_err(nc_err("encode"))?;
        Ok(bytes)
    }
}

fn write_group(b: &mut NcFileBuilder, g: &Group) -> Result<()> {
    let name = g.name.as_str();
    for (k, v) in &g.attributes {
        b.add_group_attribute(name, k.as_str(), NcAttrValue::Chars(v.clone())).map_err(nc_err(name))?;
    }
    // Dimensions in first-use order, each with an integer coordinate variable.
    let mut dims: Vec<(String, usize, netcdf_writer::DimensionId)> = Vec::new();
    for v in &g.variables {
        for (d, l) in &v.dims {
            if dims.iter().all(|(n, _, _)| n != d) {
                let id = b.add_dimension_path(format!("{name}/{d}"), *l as u64).map_err(nc_err(name))?;
                let coord = b.add_variable_path::<i64>(format!("{name}/{d}"), &[id]).map_err(nc_err(name))?;
                let index: Vec<i64> = (0..*l as i64).collect();
                b.write_variable(coord, &index).map_err(nc_err(name))?;
                dims.push((d.clone(), *l, id));
            }
        }
    }
    for v in &g.variables {
        let ids: Vec<_> =
            v.dims.iter().map(|(d, _)| dims.iter().find(|(n, _, _)| n == d).expect("registered above").2).collect();
        let var = b.add_variable_path::<f64>(format!("{name}/{}", v.name), &ids).map_err(nc_err(name))?;
        b.write_variable(var, &v.values).map_err(nc_err(name))?;
    }
    Ok(())
}
