//! Traversal statistics through a type parameter: walkers and stores add what a ray cost to a
//! [`Tally`], and callers that do not ask pay nothing ([`NoTally`] is zero-sized and its methods
//! are empty, so the counting compiles away).

/// What a traversal reports as it goes: the cells it visits and the primitives it tests.
pub trait Tally {
    /// One grid cell visited (either level).
    fn cell(&mut self);
    /// `n` primitive intersection tests (objects or triangles).
    fn tests(&mut self, n: u32);
}

/// The tally of callers that do not want the statistics: counts nothing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoTally;

impl Tally for NoTally {
    #[inline(always)]
    fn cell(&mut self) {}

    #[inline(always)]
    fn tests(&mut self, _n: u32) {}
}
