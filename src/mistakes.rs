//! The catalogue of mistakes students make when they write a Whitted ray tracer.
//!
//! Each [`Mistake`] is a switch of the one tracer (DESIGN §2): `RenderSettings.mistakes` holds a
//! [`Mistakes`] set, and the code that a student gets wrong checks it at the exact line where
//! the wrong code would be (`if settings.mistakes.has(Mistake::ReflectSign) { … }`). There is
//! never a second copy of a formula: the wrong variant is a one-line branch next to the right
//! one. With the set empty every check is a test of a zero `u64`, so the correct path is
//! unchanged and not measurably slower.

use std::fmt;

macro_rules! catalogue {
    ($( $variant:ident = $name:literal, $does:literal, $breaks:literal; )*) => {
        /// One mistake of the catalogue. Names are kebab-case and stable (scripts and the book
        /// use them).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(u8)]
        pub enum Mistake {
            $( $variant, )*
        }

        impl Mistake {
            /// Every mistake, in catalogue order.
            pub const ALL: &'static [Mistake] = &[ $( Mistake::$variant, )* ];

            /// The kebab-case name (`--mistake NAME`).
            pub fn name(self) -> &'static str {
                match self { $( Mistake::$variant => $name, )* }
            }

            /// What the wrong code does, in one sentence.
            pub fn does(self) -> &'static str {
                match self { $( Mistake::$variant => $does, )* }
            }

            /// The formula of the lecture it breaks.
            pub fn breaks(self) -> &'static str {
                match self { $( Mistake::$variant => $breaks, )* }
            }
        }
    };
}

catalogue! {
    NormalNotNormalized = "normal-not-normalized",
        "the normal is not normalised after the inverse transpose, so objects scaled down are lit too brightly and objects scaled up too darkly",
        "n_world = normalize((M⁻¹)ᵀ · n_object)";
    NormalObjectMatrix = "normal-object-matrix",
        "the normal goes through the object's matrix M instead of its inverse transpose, so non-uniformly scaled objects get tilted normals",
        "n_world = normalize((M⁻¹)ᵀ · n_object)";
    ShadowAcne = "shadow-acne",
        "shadow rays start exactly on the surface, without an offset, so they hit the surface they leave (speckled shadows)",
        "shadow ray origin p + ε·n";
    ReflectionAcne = "reflection-acne",
        "reflection rays start exactly on the surface, without an offset, so they hit the surface they leave",
        "reflected ray origin p + ε·n";
    NDotLUnclamped = "n-dot-l-unclamped",
        "n·l is not clamped at 0, so a light behind the surface subtracts diffuse light",
        "kd·Od·max(0, n·l)";
    SpecularBehindLight = "specular-behind-light",
        "specular is added where the light is behind the surface (n·l ≤ 0)",
        "specular only where n·l > 0: ks·Os·max(0, r·v)ⁿ";
    ReflectSign = "reflect-sign",
        "the reflection vector has the wrong sign: r = l − 2(n·l)n for highlights, and mirror rays −(d − 2(d·n)n) that point into the surface",
        "r = 2(n·l)n − l, reflected ray d − 2(d·n)n";
    DirectionalNotNegated = "directional-not-negated",
        "a directional light's direction is used as l without negating it, so directional lights light the far side",
        "l = −dir for a directional light";
    NoAttenuation = "no-attenuation",
        "f_att is ignored (always 1)",
        "f_att = min(1, 1/(c1 + c2·d + c3·d²))";
    AttenuationUnclamped = "attenuation-unclamped",
        "f_att without the min(1, ·), so near lights are brighter than their colour",
        "f_att = min(1, 1/(c1 + c2·d + c3·d²))";
    AmbientTimesLight = "ambient-times-light",
        "ambient is added once per light, multiplied by that light's colour, instead of once",
        "I = ka·Oa + Σ_lights f_att·I_l·(…)";
    NoGlobalCoefficients = "no-global-coefficients",
        "the global weights ka, kd, ks (and kt) are ignored (taken as 1)",
        "I = ka·Oa + Σ f_att·I_l·(kd·Od·(n·l) + ks·Os·(r·v)ⁿ) + ks·Or·I_r";
    ObjectSpaceT = "object-space-t",
        "t is compared across objects in their own object spaces: the object-space direction is normalised before intersecting, so scaled objects hide or show through others",
        "t of p = o + t·d is the same in world and object space only with d = M⁻¹·d_world unnormalised";
    ShadowBeyondLight = "shadow-beyond-light",
        "shadow rays towards a point light are blocked by objects beyond the light",
        "a shadow ray to a point light only counts hits with t < distance to the light";
    RecursionUnclamped = "recursion-unclamped",
        "recursive colours are not clamped to [0, 1] before the parent uses them (where each ray is clamped: course scenefiles, or render.clamp_each_ray)",
        "I_r = clamp(trace(reflected ray), 0, 1)";
    ReflectionWithoutKs = "reflection-without-ks",
        "the reflected term is weighted by Or alone, not ks·Or",
        "+ ks·Or·I_r";
    TextureVFlipped = "texture-v-flipped",
        "the texture is upside down: row v·h is read from the top instead of from the bottom",
        "texel row = floor((1 − v)·m·h) mod h";
    TextureUMirrored = "texture-u-mirrored",
        "the texture is mirrored left to right (u taken as 1 − u)",
        "texel column = floor(u·m·w) mod w";
    TextureTimesDiffuse = "texture-times-diffuse",
        "the texel is multiplied by kd·Od in the blend instead of replacing its share of it",
        "diffuse = (1 − blend)·kd·Od + blend·texel";
    TextureOffByOne = "texture-off-by-one",
        "the texel index is rounded instead of floored, so the texture shifts half a texel and the last half column wraps to the first",
        "texel = floor(u·m·w) mod w";
    SrgbGamma = "srgb-gamma",
        "an sRGB curve is applied to the bytes where the course writes linear values",
        "byte = floor(255·clamp(c, 0, 1)), no transfer curve";
    RoundBytes = "round-bytes",
        "bytes are rounded instead of truncated",
        "byte = floor(255·clamp(c, 0, 1))";
    PixelCorner = "pixel-corner",
        "rays go through pixel corners instead of centres",
        "x = (i + 0.5)/W − 0.5, y = 0.5 − (j + 0.5)/H";
    FovWidthAngle = "fov-width-angle",
        "the width angle is taken as aspect × height angle instead of from tan(w/2) = aspect·tan(h/2)",
        "tan(θw/2) = (W/H)·tan(θh/2)";
    AspectIgnored = "aspect-ignored",
        "the film is square whatever the image's aspect ratio, so the image is stretched",
        "tan(θw/2) = (W/H)·tan(θh/2)";
    ImageFlipped = "image-flipped",
        "the image is upside down (row 0 taken as the bottom of the film)",
        "y = 0.5 − (j + 0.5)/H: row 0 is the top";
    ConeNormal = "cone-normal",
        "the cone's side normal drops the slope: (x, 0, z), the cylinder's normal, instead of the gradient of the cone",
        "cone side normal ∝ ∇(x² + z² − k²(y − y_apex)²) = (x, −k²(y − y_apex), z), k = r/h";
    CapRadius = "cap-radius",
        "a cap is accepted at x² + z² ≤ r instead of r², so a cap of radius 0.5 grows to √0.5 past the body",
        "cap hit when x² + z² ≤ r²";
    SpotLinearFalloff = "spot-linear-falloff",
        "the spot light's penumbra falls off linearly instead of smoothly",
        "falloff = −2t³ + 3t², t = (x − inner)/(outer − inner)";
    SpotFullAngle = "spot-full-angle",
        "the spot angle is taken as the full cone angle, so the spot is half as wide",
        "angle is the half angle between the axis and the edge of the cone";
    ShininessZero = "shininess-zero",
        "shininess 0 gives (r·v)⁰ = 1 everywhere, a flat specular wash, instead of no highlight",
        "a material with n = 0 has no specular highlight";
    BlinnPhong = "blinn-phong",
        "the half vector's (n·h)ⁿ is used instead of the lecture's (r·v)ⁿ, so highlights are wider",
        "ks·Os·max(0, r·v)ⁿ";
    IntersectPointLights = "intersect-point-lights",
        "point and spot lights are lit in the Intersect stage, which renders directional lights only",
        "the Intersect stage: directional lights only";
    IntersectShadows = "intersect-shadows",
        "shadows are cast in the Intersect stage, which has none",
        "the Intersect stage: no shadow rays";
    NoAmbient = "no-ambient",
        "the ambient term is left out, so every unlit or shadowed point is black",
        "I = ka·Oa + Σ f_att·I_l·(…)";
    ShadowRayUnnormalized = "shadow-ray-unnormalized",
        "the shadow ray's direction is light − p, not made unit length, yet blockers are still counted up to t = distance, so they count out to distance² (beyond a light farther than 1, short of one nearer)",
        "shadow ray p + t·l with l unit and 0 < t < distance to the light";
    RefractionEtaInverted = "refraction-eta-inverted",
        "η in Snell's law is inverted (η₂/η₁ instead of η₁/η₂), so glass bends rays the wrong way",
        "η₁ sin θ₁ = η₂ sin θ₂: t = η·d + (η·cos θi − cos θt)·n with η = η₁/η₂";
}

impl Mistake {
    /// The mistake of a kebab-case name.
    pub fn parse(name: &str) -> Option<Mistake> {
        Mistake::ALL.iter().copied().find(|m| m.name() == name)
    }

    /// The catalogue name closest to `name` (edit distance), for "did you mean" messages.
    pub fn nearest(name: &str) -> Mistake {
        *Mistake::ALL
            .iter()
            .min_by_key(|m| crate::error::edit_distance(name, m.name()))
            .expect("the catalogue is not empty")
    }

    /// Parses a comma-separated list of names; the error names the unknown one and the
    /// nearest known name, or says that the list names none.
    pub fn parse_list(list: &str) -> Result<Mistakes, String> {
        if list.split(',').all(|name| name.trim().is_empty()) {
            return Err("no name given (rtlab mistakes lists the names)".into());
        }
        let mut set = Mistakes::NONE;
        for part in list.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            match Mistake::parse(part) {
                Some(m) => set = set.with(m),
                None => {
                    return Err(format!(
                        "unknown mistake \"{part}\" (did you mean \"{}\"? `rtlab mistakes` lists them all)",
                        Mistake::nearest(part).name()
                    ))
                }
            }
        }
        Ok(set)
    }
}

impl fmt::Display for Mistake {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A set of mistakes: a `u64` bitset, `Copy`, so the tracer's checks cost one AND.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Mistakes(u64);

impl Mistakes {
    /// No mistake: the correct tracer.
    pub const NONE: Mistakes = Mistakes(0);

    /// Whether `m` is in the set.
    #[inline(always)]
    pub fn has(self, m: Mistake) -> bool {
        self.0 & (1u64 << m as u8) != 0
    }

    /// Whether a mistake of the set changes which object a ray hits (`cap-radius`,
    /// `object-space-t`, `cone-normal`): the BVH and camera-ray bundles cannot be trusted
    /// under it, so rays take the lecture's loop over every object.
    pub fn changes_hits(self) -> bool {
        self.has(Mistake::CapRadius)
            || self.has(Mistake::ObjectSpaceT)
            || self.has(Mistake::ConeNormal)
    }

    /// The set with `m` added.
    pub fn with(self, m: Mistake) -> Mistakes {
        Mistakes(self.0 | (1u64 << m as u8))
    }

    /// The set of one mistake.
    pub fn one(m: Mistake) -> Mistakes {
        Mistakes::NONE.with(m)
    }

    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The mistakes in the set, in catalogue order.
    pub fn iter(self) -> impl Iterator<Item = Mistake> {
        Mistake::ALL.iter().copied().filter(move |m| self.has(*m))
    }

    /// Names, comma-separated (the form `--mistake` accepts).
    pub fn names(self) -> String {
        self.iter().map(Mistake::name).collect::<Vec<_>>().join(",")
    }
}

impl FromIterator<Mistake> for Mistakes {
    fn from_iter<I: IntoIterator<Item = Mistake>>(iter: I) -> Self {
        iter.into_iter().fold(Mistakes::NONE, Mistakes::with)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_fit_the_bitset() {
        assert!(Mistake::ALL.len() <= 64);
        for (i, m) in Mistake::ALL.iter().enumerate() {
            assert_eq!(*m as usize, i);
            assert_eq!(Mistake::parse(m.name()), Some(*m));
            assert!(!m.does().is_empty() && !m.breaks().is_empty());
        }
    }

    #[test]
    fn set_and_parse_list() {
        let s = Mistake::parse_list("reflect-sign, cap-radius").unwrap();
        assert!(s.has(Mistake::ReflectSign) && s.has(Mistake::CapRadius));
        assert!(!s.has(Mistake::ShadowAcne));
        assert_eq!(s.names(), "reflect-sign,cap-radius");
        let e = Mistake::parse_list("reflect-sing").unwrap_err();
        assert!(e.contains("did you mean \"reflect-sign\""), "{e}");
        assert!(Mistakes::NONE.is_empty());
    }
}
