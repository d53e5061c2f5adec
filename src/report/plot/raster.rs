//! The PNG backend of the plots: [`BitMapBackend`] with its text drawn here. Plotters 0.3.7
//! places each `ab_glyph` glyph at the pen position without its left side bearing, so "13"
//! reads "1 3"; this backend lays text out from the bundled DejaVu Sans with bearings, kerning
//! and sub-pixel positions, and centres it vertically on the cap height so that tick labels sit
//! level with their ticks. Everything else goes to the bitmap backend unchanged.

use ab_glyph::{point, Font, FontRef, Glyph, PxScale, ScaleFont};
use plotters::prelude::{BitMapBackend, DrawingBackend};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};

/// A bitmap backend whose text is laid out by [`Raster::layout`].
pub(super) struct Raster<'a> {
    inner: BitMapBackend<'a>,
    font: FontRef<'static>,
    /// Cap height per pixel of [`PxScale`] (the height of "H" at scale 1).
    cap_per_px: f32,
}

type Error<'a> = DrawingErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>;

/// One line of positioned glyphs, baseline at y = 0, starting at x = 0.
struct Line {
    glyphs: Vec<Glyph>,
    width: f32,
    ascent: f32,
    descent: f32,
    cap: f32,
}

impl<'a> Raster<'a> {
    /// Wraps `inner`, drawing text with `font` (the bytes of a TrueType font); `None` when the
    /// font does not parse.
    pub(super) fn new(inner: BitMapBackend<'a>, font: &'static [u8]) -> Option<Self> {
        let font = FontRef::try_from_slice(font).ok()?;
        let h = font.glyph_id('H').with_scale_and_position(100.0, point(0.0, 0.0));
        let cap_per_px = font.outline_glyph(h).map_or(0.7, |o| -o.px_bounds().min.y / 100.0);
        Some(Raster { inner, font, cap_per_px })
    }

    /// Lays `text` out at `size` pixels (the line height, ascent to descent, as in plotters).
    fn layout(&self, text: &str, size: f64) -> Line {
        let scale = PxScale::from(size as f32);
        let font = self.font.as_scaled(scale);
        let mut glyphs = Vec::with_capacity(text.len());
        let (mut x, mut prev) = (0.0, None);
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                x += font.kern(p, id);
            }
            glyphs.push(id.with_scale_and_position(scale, point(x, 0.0)));
            x += font.h_advance(id);
            prev = Some(id);
        }
        Line {
            glyphs,
            width: x,
            ascent: font.ascent(),
            descent: font.descent(),
            cap: self.cap_per_px * scale.y,
        }
    }
}

impl<'a> DrawingBackend for Raster<'a> {
    type ErrorType = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), Error<'a>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), Error<'a>> {
        self.inner.present()
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<(), Error<'a>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), Error<'a>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), Error<'a>> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> Result<(), Error<'a>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), Error<'a>> {
        let colour = style.color();
        if colour.alpha == 0.0 {
            return Ok(());
        }
        let line = self.layout(text, style.size());
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -line.width / 2.0,
            HPos::Right => -line.width,
        };
        // Where the baseline goes below the anchor.
        let dy = match anchor.v_pos {
            VPos::Top => line.ascent,
            VPos::Center => line.cap / 2.0,
            VPos::Bottom => line.descent,
        };
        let transform = style.transform();
        let (w, h) = self.inner.get_size();
        let mut result = Ok(());
        for mut glyph in line.glyphs {
            glyph.position = point(glyph.position.x + dx, glyph.position.y + dy);
            let Some(outline) = self.font.outline_glyph(glyph) else { continue };
            let bounds = outline.px_bounds();
            let (x0, y0) = (bounds.min.x as i32, bounds.min.y as i32);
            outline.draw(|x, y, coverage| {
                if result.is_err() || coverage <= 0.0 {
                    return;
                }
                let (tx, ty) = transform.transform(x0 + x as i32, y0 + y as i32);
                let (px, py) = (pos.0 + tx, pos.1 + ty);
                if px >= 0 && py >= 0 && (px as u32) < w && (py as u32) < h {
                    result = self.inner.draw_pixel((px, py), colour.mix(f64::from(coverage.min(1.0))));
                }
            });
        }
        result
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), Error<'a>> {
        let line = self.layout(text, style.size());
        Ok((line.width.ceil() as u32, (line.ascent - line.descent).ceil() as u32))
    }
}
