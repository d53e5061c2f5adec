//! The column arrays the structure-of-arrays layout is made of: three coordinate arrays per
//! vector (`Xyz`) and four column vectors per affine map (`Affines`).

use crate::math::{Affine3A, Vec3};

/// Three coordinate arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Xyz {
    pub(super) x: Vec<f32>,
    pub(super) y: Vec<f32>,
    pub(super) z: Vec<f32>,
}

impl Xyz {
    #[inline]
    pub(super) fn push(&mut self, v: Vec3) {
        self.x.push(v.x);
        self.y.push(v.y);
        self.z.push(v.z);
    }

    #[inline]
    pub(super) fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    /// The coordinate array of `axis` (0, 1 or 2).
    #[inline(always)]
    pub(super) fn axis(&self, axis: usize) -> &[f32] {
        match axis {
            0 => &self.x,
            1 => &self.y,
            _ => &self.z,
        }
    }

    pub(super) fn bytes(&self) -> usize {
        3 * self.x.len() * std::mem::size_of::<f32>()
    }
}

/// Four column arrays of affine maps.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Affines {
    x: Xyz,
    y: Xyz,
    z: Xyz,
    w: Xyz,
}

impl Affines {
    pub(super) fn push(&mut self, m: &Affine3A) {
        self.x.push(m.matrix3.x_axis.into());
        self.y.push(m.matrix3.y_axis.into());
        self.z.push(m.matrix3.z_axis.into());
        self.w.push(m.translation.into());
    }

    #[inline]
    pub(super) fn get(&self, i: usize) -> Affine3A {
        Affine3A::from_cols(
            self.x.get(i).into(),
            self.y.get(i).into(),
            self.z.get(i).into(),
            self.w.get(i).into(),
        )
    }

    pub(super) fn bytes(&self) -> usize {
        self.x.bytes() + self.y.bytes() + self.z.bytes() + self.w.bytes()
    }
}
