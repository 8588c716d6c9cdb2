//! The bundle's two tests on one box, with their working: what `rtlab intersect box
//! --bundle-to` shows. It runs the walk's own functions, [`RayBundle::new`],
//! `interval_enter` and `lane_enter`, and each ray's own slab test ([`Node::enter`]), on a
//! node that holds just that box; nothing here tests anything itself.

use super::{RayBundle, BUNDLE};
use crate::accel::bvh::{down, up, Node};
use crate::accel::isa::{self, Kernel, Wide};
use crate::accel::lanes::F32s;
use crate::math::Ray;
use crate::shapes::Aabb;

/// One ray's verdicts on the box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayVerdict {
    /// The lane test's bit for this ray (`None`: the bundle is not sign-coherent, and the
    /// walk sends each ray alone, with its own slab test).
    pub lane: Option<bool>,
    /// The ray's own slab test, as a ray walking alone runs it: does it enter, and a t no
    /// later than its entry (when it does).
    pub own: bool,
    pub t_enter: f32,
}

/// The working of the bundle's tests on one box, in `f32` as the walk computes it.
#[derive(Debug, Clone, PartialEq)]
pub struct BundleWorking {
    /// The box as the BVH stores it (its f64 corners rounded outwards to f32).
    pub min: [f32; 3],
    pub max: [f32; 3],
    /// Every direction has one sign per axis: the bundle may walk together.
    pub coherent: bool,
    /// Per axis (x, y, z): every direction has one sign along it (the sign of d, which is
    /// the sign of 1/d the walk compares; +0 counts as positive, −0 as negative).
    /// `coherent` is all three.
    pub coherent_axes: [bool; 3],
    /// Every ray starts at the same point.
    pub shared_origin: bool,
    /// Per axis, the bundle's bounds: a t no later than any ray's entry into that slab and
    /// one no earlier than any ray's exit. `None`: the axis bounds nothing (some ray's 1/d
    /// along it is ±∞: a direction of 0 there, or below about 3·10⁻³⁹ in f32), or the
    /// bundle is not sign-coherent and no interval test is made.
    pub axes: [Option<(f32, f32)>; 3],
    /// The bundle's bounds over the three axes, widened for rounding, as the verdict
    /// compares them: the latest entry (no earlier than t = 0) and the earliest exit.
    /// `None` when no interval test is made.
    pub together: Option<(f32, f32)>,
    /// The interval test's verdict: some ray may enter (false: culled for every ray).
    /// `None` when the bundle is not sign-coherent: the walk then sends each ray alone.
    pub kept: Option<bool>,
    /// Each ray's verdicts, in order.
    pub rays: Vec<RayVerdict>,
}

impl BundleWorking {
    /// The names of the axes.
    pub const AXES: [&'static str; 3] = ["x", "y", "z"];

    /// The axes along which the directions change sign, for text: "x", "x and y",
    /// "x, y and z" ("no axis" for a sign-coherent bundle).
    pub fn mixed_axes(&self) -> String {
        let names: Vec<&str> = (0..3)
            .filter(|&k| !self.coherent_axes[k])
            .map(|k| Self::AXES[k])
            .collect();
        match names.as_slice() {
            [] => "no axis".into(),
            [one] => one.to_string(),
            [init @ .., last] => format!("{} and {last}", init.join(", ")),
        }
    }
}

/// The interval test and the lane test of up to [`BUNDLE`] rays (t ≥ 0) against one box.
pub fn bundle_working(rays: &[Ray], bounds: &Aabb) -> BundleWorking {
    assert!((1..=BUNDLE).contains(&rays.len()), "1 to {BUNDLE} rays");
    let mut node = Node::EMPTY;
    for k in 0..3 {
        node.planes[0][k][0] = down(bounds.min[k]);
        node.planes[1][k][0] = up(bounds.max[k]);
    }
    isa::run(Working { rays, node })
}

struct Working<'a> {
    rays: &'a [Ray],
    node: Node,
}

impl Kernel for Working<'_> {
    type Output = BundleWorking;
    fn run<W: Wide>(self, w: W) -> BundleWorking {
        let (node, t_min) = (&self.node, 0.0f32);
        let b = RayBundle::new(w, self.rays);
        let (mut axes, mut together) = ([None; 3], (0.0, 0.0));
        let kept = b.interval_enter(node, t_min, |axis, enter, exit| match axis {
            Some(k) => axes[k] = Some((enter.0[0], exit.0[0])),
            None => together = (enter.0[0], exit.0[0]),
        }) & 1
            != 0;
        let far = w.load(&F32s::splat(f32::INFINITY));
        let lanes = match (b.coherent, b.shared_origin) {
            (false, _) => None,
            (true, true) => Some(b.lane_enter::<W, true>(w, node, 0, t_min, far, b.all).0),
            (true, false) => Some(b.lane_enter::<W, false>(w, node, 0, t_min, far, b.all).0),
        };
        let rays = (0..self.rays.len())
            .map(|i| {
                let (own, t) = node.enter::<false>(&b.ray_box(i), t_min, f32::INFINITY);
                RayVerdict {
                    lane: lanes.map(|m| m >> i & 1 != 0),
                    own: own & 1 != 0,
                    t_enter: t[0],
                }
            })
            .collect();
        // The walk's `coherent` is the sign of each lane's 1/d agreeing on every axis; the
        // sign of d is the same sign, so this splits the walk's verdict axis by axis.
        let coherent_axes = std::array::from_fn(|k| {
            let negative = |i: usize| b.dir[k].0[i].is_sign_negative();
            (0..self.rays.len()).all(|i| negative(i) == negative(0))
        });
        assert_eq!(
            b.coherent,
            coherent_axes == [true; 3],
            "the per-axis signs disagree with the walk's sign coherence"
        );
        BundleWorking {
            min: std::array::from_fn(|k| node.planes[0][k][0]),
            max: std::array::from_fn(|k| node.planes[1][k][0]),
            coherent: b.coherent,
            coherent_axes,
            shared_origin: b.shared_origin,
            axes,
            together: b.coherent.then_some(together),
            kept: b.coherent.then_some(kept),
            rays,
        }
    }
}
