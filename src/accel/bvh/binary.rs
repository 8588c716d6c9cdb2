//! The binary tree the SAH builder makes ([`super::build`]) and the collapse reads
//! ([`super::collapse`]): its nodes, and the build-time boxes they are made from.

use super::slab::{down, up};
use crate::shapes::Aabb;
use glam::Vec3A;

/// One node of the binary tree the SAH builder makes: an f32 box and either two children
/// (`count == 0`: children at `first` and `first + 1`) or a run of `count` primitives
/// starting at `first` in `prims`. The builder's output only: [`Bvh::build`](super::Bvh::build) collapses it
/// into four-wide [`Node`](super::Node)s, which is what rays traverse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BinNode {
    pub(super) min: [f32; 3],
    pub(super) first: u32,
    pub(super) max: [f32; 3],
    pub(super) count: u32,
}

impl BinNode {
    /// A slot of the builder's array no node took.
    pub(super) const UNUSED: BinNode = BinNode {
        min: [0.0; 3],
        first: 0,
        max: [0.0; 3],
        count: 0,
    };

    pub(super) fn is_leaf(&self) -> bool {
        self.count > 0
    }

    pub(super) fn half_area(&self) -> f32 {
        FBox {
            min: Vec3A::from_array(self.min),
            max: Vec3A::from_array(self.max),
        }
        .half_area()
    }
}

/// A build-time box in f32, already rounded outwards. `Vec3A` (16 bytes, SIMD) so that a
/// union is one `minps` and one `maxps`: binning is most of the build's time.
#[derive(Debug, Clone, Copy)]
pub(super) struct FBox {
    pub(super) min: Vec3A,
    pub(super) max: Vec3A,
}

impl FBox {
    pub(super) const EMPTY: FBox = FBox {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };
    pub(super) fn from_f64(b: &Aabb) -> FBox {
        FBox {
            min: Vec3A::new(down(b.min.x), down(b.min.y), down(b.min.z)),
            max: Vec3A::new(up(b.max.x), up(b.max.y), up(b.max.z)),
        }
    }
    // Build boxes hold no NaN, so glam's min and max (minps, maxps) need no NaN rule.
    #[inline(always)]
    pub(super) fn union(self, o: FBox) -> FBox {
        FBox {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    #[inline(always)]
    pub(super) fn grow(self, p: Vec3A) -> FBox {
        FBox {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    pub(super) fn half_area(&self) -> f32 {
        let e = self.max - self.min;
        if e.x < 0.0 {
            return 0.0;
        }
        e.x * e.y + e.y * e.z + e.z * e.x
    }
    pub(super) fn node(&self, first: u32, count: u32) -> BinNode {
        BinNode {
            min: self.min.to_array(),
            first,
            max: self.max.to_array(),
            count,
        }
    }
}
