//! The YAML beam description (a public contract: field names never change).
//!
//! Lengths are in nanometres, everything else in SI; every field name carries
//! its unit. Unknown fields are rejected by serde, out-of-range values by
//! [`BeamSpec::validate`].

use serde::{Deserialize, Serialize};

use crate::error::{non_negative, positive, InputError};

/// Boundary conditions at x = 0 and x = L.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Support {
    /// w = 0 at both ends (rotations free).
    SimplySupported,
    /// w = w' = 0 at both ends.
    ClampedClamped,
    /// w = w' = 0 at x = 0, free at x = L (cantilever).
    ClampedFree,
    /// w = w' = 0 at x = 0, w = 0 at x = L.
    ClampedPinned,
}

impl Support {
    pub const ALL: [Support; 4] =
        [Support::SimplySupported, Support::ClampedClamped, Support::ClampedFree, Support::ClampedPinned];

    pub fn name(self) -> &'static str {
        match self {
            Support::SimplySupported => "simply-supported",
            Support::ClampedClamped => "clamped-clamped",
            Support::ClampedFree => "clamped-free",
            Support::ClampedPinned => "clamped-pinned",
        }
    }
}

/// One internal variable of the relaxation kernel, eq. (8):
/// E_rel(t) = E [1 + Σ Δi exp(−Ωi t)].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InternalVariable {
    /// Relaxation amplitude Δi (dimensionless, ≥ 0).
    pub delta: f64,
    /// Inverse relaxation time Ωi in rad/s (> 0).
    pub omega_rad_s: f64,
}

/// A point mass rigidly attached to the beam axis (model extension, default off).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMass {
    /// Mass in kg (> 0).
    pub mass_kg: f64,
    /// Position along the beam in nm, 0 ≤ x ≤ length_nm.
    pub x_nm: f64,
}

/// Shear deformation and rotary inertia (nonlocal Timoshenko beam, extension,
/// default off). The shear modulus is G = E/(2(1 + ν)); E and G relax
/// together (ν is constant), so the relaxation factor multiplies the whole
/// elastic stiffness (bending + shear).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShearDeformation {
    /// Poisson's ratio ν, −1 < ν ≤ 0.5 (isotropic elasticity).
    pub poisson_ratio: f64,
    /// Timoshenko shear coefficient κ, 0 < κ ≤ 1 (solid circle: 6(1+ν)/(7+6ν) ≈ 0.9).
    pub shear_coefficient: f64,
}

impl ShearDeformation {
    /// κG/E = κ/(2(1 + ν)).
    pub fn shear_to_youngs(&self) -> f64 {
        self.shear_coefficient / (2.0 * (1.0 + self.poisson_ratio))
    }
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// A beam as written in YAML.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamSpec {
    pub length_nm: f64,
    /// Solid circular section: A = πd²/4, I = πd⁴/64.
    pub diameter_nm: f64,
    pub youngs_modulus_pa: f64,
    pub density_kg_m3: f64,
    pub support: Support,
    /// Number of Hermite beam elements.
    pub elements: usize,
    /// Eringen nonlocal parameter e0a in nm, eq. (5).
    #[serde(default)]
    pub nonlocal_e0a_nm: f64,
    /// External viscous damping C of eq. (13), N·s/m².
    #[serde(default)]
    pub viscous_damping_n_s_m2: f64,
    /// Internal variables (Δi, Ωi) of eq. (8); empty = elastic.
    #[serde(default)]
    pub internal_variables: Vec<InternalVariable>,
    /// Rotational spring at each supported end, N·m/rad (extension, default 0).
    #[serde(default)]
    pub support_rotational_stiffness_n_m_rad: f64,
    /// Attached point mass (extension, default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_mass: Option<PointMass>,
    /// Axial force N in newtons, tension > 0, compression < 0 (extension,
    /// default 0). Elastic: not multiplied by the relaxation factor.
    /// Compression must stay above the (nonlocal) buckling load of the
    /// beam's mesh and support (checked by [`BeamSpec::validate`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub axial_force_n: f64,
    /// Shear deformation and rotary inertia (Timoshenko beam; default off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_deformation: Option<ShearDeformation>,
}

/// Largest element count accepted: far beyond convergence, keeps dense paths bounded.
pub const MAX_ELEMENTS: usize = 2000;

impl BeamSpec {
    /// Checks every documented range; the error names the field, value and allowed range.
    pub fn validate(&self) -> Result<(), InputError> {
        positive("length_nm", self.length_nm)?;
        positive("diameter_nm", self.diameter_nm)?;
        positive("youngs_modulus_pa", self.youngs_modulus_pa)?;
        positive("density_kg_m3", self.density_kg_m3)?;
        if self.elements == 0 || self.elements > MAX_ELEMENTS {
            return Err(InputError::new("elements", self.elements, format!("1..={MAX_ELEMENTS}")));
        }
        non_negative("nonlocal_e0a_nm", self.nonlocal_e0a_nm)?;
        non_negative("viscous_damping_n_s_m2", self.viscous_damping_n_s_m2)?;
        for (i, iv) in self.internal_variables.iter().enumerate() {
            non_negative(&format!("internal_variables[{i}].delta"), iv.delta)?;
            positive(&format!("internal_variables[{i}].omega_rad_s"), iv.omega_rad_s)?;
        }
        non_negative("support_rotational_stiffness_n_m_rad", self.support_rotational_stiffness_n_m_rad)?;
        if let Some(pm) = &self.point_mass {
            positive("point_mass.mass_kg", pm.mass_kg)?;
            if !(pm.x_nm.is_finite() && pm.x_nm >= 0.0 && pm.x_nm <= self.length_nm) {
                return Err(InputError::new(
                    "point_mass.x_nm",
                    pm.x_nm,
                    format!("0 <= x_nm <= length_nm = {}", self.length_nm),
                ));
            }
        }
        self.validate_extensions()?;
        Ok(())
    }

    /// The axial force and shear-deformation fields (issue 13), including the
    /// buckling bound of a compressive force.
    fn validate_extensions(&self) -> Result<(), InputError> {
        if !self.axial_force_n.is_finite() {
            return Err(InputError::new("axial_force_n", self.axial_force_n, "finite (tension > 0, compression < 0)"));
        }
        if let Some(sd) = &self.shear_deformation {
            let nu = sd.poisson_ratio;
            if !(nu.is_finite() && nu > -1.0 && nu <= 0.5) {
                return Err(InputError::new("shear_deformation.poisson_ratio", nu, "-1 < poisson_ratio <= 0.5"));
            }
            let k = sd.shear_coefficient;
            if !(k.is_finite() && k > 0.0 && k <= 1.0) {
                return Err(InputError::new("shear_deformation.shear_coefficient", k, "0 < shear_coefficient <= 1"));
            }
        }
        if self.axial_force_n < 0.0 {
            crate::beam::model::check_buckling(self)?;
        }
        Ok(())
    }

    /// Cross-section area in m².
    pub fn area_m2(&self) -> f64 {
        let d = self.diameter_nm * 1e-9;
        std::f64::consts::PI * d * d / 4.0
    }

    /// Second moment of area in m⁴.
    pub fn inertia_m4(&self) -> f64 {
        let d = self.diameter_nm * 1e-9;
        std::f64::consts::PI * d.powi(4) / 64.0
    }

    /// Parses YAML (unknown fields rejected) and validates. Parse errors are
    /// reported as an [`InputError`] on the field serde names.
    pub fn from_yaml(text: &str) -> Result<Self, InputError> {
        let spec: BeamSpec = crate::error::parse_yaml(text)?;
        spec.validate()?;
        Ok(spec)
    }
}
