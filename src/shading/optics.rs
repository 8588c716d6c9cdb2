//! Mirror reflection and Snell's law, with total internal reflection as a visible `None`.

use glam::DVec3;

// ANCHOR: reflect
/// The mirror direction of `d` about the unit normal `n`: d − 2(d·n)n.
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}
// ANCHOR_END: reflect

// ANCHOR: refract
/// Snell's law for unit `d` arriving at a surface with unit normal `n` facing the incoming
/// side, going from index η₁ into η₂ (`eta` = η₁/η₂): returns the transmitted direction, or
/// `None` for total internal reflection (sin θt would exceed 1).
pub fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(eta * d + (eta * cos_i - cos_t) * n)
}
// ANCHOR_END: refract

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn snell_and_tir() {
        // 45° into glass (1 → 1.5): sin θt = sin 45° / 1.5.
        let d = DVec3::new(1.0, -1.0, 0.0).normalize();
        let t = refract(d, DVec3::Y, 1.0 / 1.5).unwrap();
        assert!((t.x - (45f64.to_radians().sin() / 1.5)).abs() < 1e-12);
        assert!((t.length() - 1.0).abs() < 1e-12);
        // Leaving glass at 45° (1.5 → 1): past the critical angle of 41.8°.
        assert!(refract(d, DVec3::Y, 1.5).is_none());
        assert_eq!(reflect(d, DVec3::Y), DVec3::new(d.x, -d.y, 0.0));
    }
}
