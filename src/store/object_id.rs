//! What a hit's object names: the one place its encoding is read.

/// A hit's object: a bounded object of the snapshot's grid (an object of the scene, or a mesh
/// instance), a plane (unbounded, tested on its own), or an object moving while the shutter is
/// open (kept out of the static grid). Packed in 32 bits, with the kind in the top two; build
/// one with [`ObjectId::bounded`], [`ObjectId::plane`] or [`ObjectId::moving`] and read it
/// with [`ObjectId::kind`].
///
/// Ids order bounded objects first, then moving ones, then planes; a shadow ray's
/// transmittance multiplies its bounded objects' shares in ascending id.
///
/// ```
/// use penumbra::store::{ObjectId, ObjectKind};
/// assert_eq!(ObjectId::plane(3).kind(), ObjectKind::Plane(3));
/// assert_eq!(ObjectId::moving(0).kind(), ObjectKind::Moving(0));
/// assert_eq!(ObjectId::bounded(7).kind(), ObjectKind::Bounded(7));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ObjectId(u32);

/// An [`ObjectId`] decoded: which table the index is into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ObjectKind {
    /// Index into the snapshot store's bounded objects (the top-level grid's ids).
    Bounded(u32),
    /// Index into the store's planes.
    Plane(u32),
    /// Index into the snapshot's moving objects.
    Moving(u32),
}

impl ObjectId {
    /// Bit marking a plane.
    const PLANE: u32 = 1 << 31;
    /// Bit marking a moving object.
    const MOVING: u32 = 1 << 30;
    /// Largest index of any kind (2^30 − 1): a larger one would run into the kind bits. Only
    /// debug builds check it; a billion objects exhaust memory first.
    pub const MAX_INDEX: u32 = Self::MOVING - 1;

    /// Bounded object `index` (at most [`ObjectId::MAX_INDEX`]).
    #[inline]
    pub const fn bounded(index: u32) -> Self {
        debug_assert!(index <= Self::MAX_INDEX);
        Self(index)
    }

    /// Plane `index`.
    #[inline]
    pub const fn plane(index: u32) -> Self {
        debug_assert!(index <= Self::MAX_INDEX);
        Self(index | Self::PLANE)
    }

    /// Moving object `index`.
    #[inline]
    pub const fn moving(index: u32) -> Self {
        debug_assert!(index <= Self::MAX_INDEX);
        Self(index | Self::MOVING)
    }

    /// Which object this is.
    #[inline]
    pub const fn kind(self) -> ObjectKind {
        if self.0 & Self::PLANE != 0 {
            ObjectKind::Plane(self.0 & !Self::PLANE)
        } else if self.0 & Self::MOVING != 0 {
            ObjectKind::Moving(self.0 & !Self::MOVING)
        } else {
            ObjectKind::Bounded(self.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_round_trips_at_the_ends_of_its_range() {
        for i in [0, 1, 12_345, ObjectId::MAX_INDEX] {
            assert_eq!(ObjectId::bounded(i).kind(), ObjectKind::Bounded(i));
            assert_eq!(ObjectId::plane(i).kind(), ObjectKind::Plane(i));
            assert_eq!(ObjectId::moving(i).kind(), ObjectKind::Moving(i));
        }
        assert!(ObjectId::bounded(ObjectId::MAX_INDEX) < ObjectId::moving(0));
        assert!(ObjectId::moving(ObjectId::MAX_INDEX) < ObjectId::plane(0));
    }
}
