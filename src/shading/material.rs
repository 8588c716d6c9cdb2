use super::Texture;
use glam::DVec3;

/// The lecture's material: O_a, O_d, O_s, shininess n, O_r, O_t, index of refraction.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub shininess: f64,
    pub reflective: DVec3,
    pub transparent: DVec3,
    /// Per-channel index of refraction; dispersion when the channels differ.
    pub ior: DVec3,
    /// `false`: non-refractive transparency, I = (1 − kt·Ot)·I_local + kt·Ot·I_behind.
    pub refract: bool,
    pub texture: Option<Texture>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: "default".into(),
            ambient: DVec3::ZERO,
            diffuse: DVec3::ONE,
            specular: DVec3::ZERO,
            shininess: 0.0,
            reflective: DVec3::ZERO,
            transparent: DVec3::ZERO,
            ior: DVec3::ONE,
            refract: true,
            texture: None,
        }
    }
}

impl Material {
    pub fn is_dispersive(&self) -> bool {
        self.ior.x != self.ior.y || self.ior.y != self.ior.z
    }
}
