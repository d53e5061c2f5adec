//! Tiles: the image cut into squares of [`TILE`] pixels, shaded in parallel and assembled in
//! tile order, so the film does not depend on which thread shaded what.

use rayon::prelude::*;

use super::finite::DropTally;
use super::settings::RenderSettings;
use super::stats::RayCounts;

use crate::film::Film;
use crate::math::Vec3;

/// Edge length of a square render tile in pixels.
pub const TILE: u32 = 16;

/// The number of tiles an image of `width` × `height` pixels is rendered in (what progress
/// observers count to).
pub fn tile_count(width: u32, height: u32) -> u32 {
    width.div_ceil(TILE) * height.div_ceil(TILE)
}

/// The output of one tile: colours, rays per pixel when the cost AOV is wanted, and the
/// samples its pixels dropped.
pub(super) type TileResult = (Vec<Vec3>, Vec<u32>, RayCounts, DropTally);

/// A rendered image before statistics: the film, ray counts, the cost image (when wanted) and
/// the dropped non-finite samples.
pub(super) struct Assembled {
    pub(super) film: Film,
    pub(super) rays: RayCounts,
    pub(super) cost: Option<Vec<u32>>,
    pub(super) dropped: DropTally,
}

/// What one tile's shader writes: per pixel in row-major order, its colour and the samples it
/// dropped, and (only when the cost AOV is wanted) the rays it traced.
#[derive(Debug, Default)]
pub(super) struct TileOut {
    pub(super) pixels: Vec<(Vec3, u32)>,
    pub(super) costs: Vec<u32>,
}

/// Runs `shade` over every tile (`[x0, y0, x1, y1]`, ends exclusive), tiles in parallel, and
/// assembles the film (and the cost image when `want_cost`: every tile then reports costs) in
/// tile order.
pub(super) fn render_tiles<F>(
    settings: &RenderSettings,
    want_cost: bool,
    shade: F,
    tile_done: &(dyn Fn() + Sync),
) -> Assembled
where
    F: Fn([u32; 4], &mut RayCounts, &mut TileOut) + Sync,
{
    let (w, h) = (settings.width, settings.height);
    let tiles_x = w.div_ceil(TILE);
    let tiles: Vec<TileResult> = (0..tiles_x * h.div_ceil(TILE))
        .into_par_iter()
        // One tile per job. Left to split the range as it likes, rayon ran a frame's last
        // stretch of tiles (a hundred or more) as one job on one thread while the other
        // waited: 6-8 ms of a 75 ms trace on the 100k spheres' twin (perf, 2 threads). A tile
        // is tens to hundreds of microseconds of work; a job costs about one.
        .with_max_len(1)
        .map(|tile| {
            let (x0, y0) = (tile % tiles_x * TILE, tile / tiles_x * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut rays = RayCounts::default();
            let mut out = TileOut { pixels: Vec::with_capacity((TILE * TILE) as usize), costs: Vec::new() };
            crate::simd::with_single_ray_level(settings.simd, || {
                shade([x0, y0, x1, y1], &mut rays, &mut out)
            });
            debug_assert_eq!(out.pixels.len() as u32, (x1 - x0) * (y1 - y0), "one entry per pixel");
            let mut dropped = DropTally::default();
            let tw = x1 - x0;
            for (k, &(_, n)) in out.pixels.iter().enumerate() {
                dropped.record((y0 + k as u32 / tw) * w + x0 + k as u32 % tw, n);
            }
            tile_done();
            (out.pixels.into_iter().map(|(c, _)| c).collect(), out.costs, rays, dropped)
        })
        .collect();
    assemble(settings, &tiles, want_cost)
}

/// The film, total counts, (if wanted) cost image and dropped samples from per-tile results
/// in tile order. Each band of tile rows is copied into the film row by row, bands in
/// parallel: the copy is the serial tail of every frame otherwise (6 % of a 640×480 frame's
/// trace time on 2 threads, measured).
pub(super) fn assemble(settings: &RenderSettings, tiles: &[TileResult], want_cost: bool) -> Assembled {
    let (w, h) = (settings.width, settings.height);
    let tiles_x = w.div_ceil(TILE) as usize;
    let band = (TILE * w) as usize;
    let mut film = Film::new(w, h);
    film.pixels
        .par_chunks_mut(band)
        .zip(tiles.par_chunks(tiles_x))
        .for_each(|(rows, band_tiles)| place(rows, band_tiles, w, |(pixels, ..)| pixels));
    // Every path (fixed samples or adaptive) reaches the film here, finite by construction.
    debug_assert!(
        film.pixels.iter().all(|c| c.is_finite()),
        "non-finite radiance at pixel index {:?}",
        film.pixels.iter().position(|c| !c.is_finite())
    );
    let cost = want_cost.then(|| {
        let mut cost = vec![0u32; w as usize * h as usize];
        cost.par_chunks_mut(band)
            .zip(tiles.par_chunks(tiles_x))
            .for_each(|(rows, band_tiles)| place(rows, band_tiles, w, |(_, costs, ..)| costs));
        cost
    });
    let mut rays = RayCounts::default();
    let mut dropped = DropTally::default();
    for (_, _, counts, drops) in tiles {
        rays.add(counts);
        dropped.add(drops);
    }
    Assembled { film, rays, cost, dropped }
}

/// Copies one band of tiles (`band_tiles`, left to right, each row-major and `TILE` wide but
/// at the right edge) into `rows`, the band's rows of an image `width` pixels wide. A tile
/// with no values (`values` empty: no cost image asked of it) leaves its pixels as they are.
fn place<T: Copy>(
    rows: &mut [T],
    band_tiles: &[TileResult],
    width: u32,
    values: impl Fn(&TileResult) -> &Vec<T>,
) {
    for (i, tile) in band_tiles.iter().enumerate() {
        let x0 = i * TILE as usize;
        let tw = TILE.min(width - x0 as u32) as usize;
        for (r, row) in values(tile).chunks(tw).enumerate() {
            let at = r * width as usize + x0;
            rows[at..at + tw].copy_from_slice(row);
        }
    }
}

pub(super) fn saturate(n: u64) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tile results whose every pixel holds its own coordinates (and a cost from them), for an
    /// image whose sides are not multiples of [`TILE`].
    fn labelled_tiles(w: u32, h: u32, with_costs: bool) -> Vec<TileResult> {
        let tiles_x = w.div_ceil(TILE);
        (0..tile_count(w, h))
            .map(|tile| {
                let (x0, y0) = (tile % tiles_x * TILE, tile / tiles_x * TILE);
                let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
                let mut pixels = Vec::new();
                let mut costs = Vec::new();
                for y in y0..y1 {
                    for x in x0..x1 {
                        pixels.push(Vec3::new(x as f32, y as f32, tile as f32));
                        if with_costs {
                            costs.push(y * w + x + 1);
                        }
                    }
                }
                let rays = RayCounts { camera: u64::from(tile) + 1, ..RayCounts::default() };
                (pixels, costs, rays, DropTally::default())
            })
            .collect()
    }

    #[test]
    fn assembly_puts_every_tile_pixel_where_it_belongs() {
        for (w, h) in [(37, 21), (16, 16), (1, 40), (50, 1)] {
            let settings = RenderSettings { width: w, height: h, ..RenderSettings::default() };
            let tiles = labelled_tiles(w, h, true);
            let Assembled { film, rays, cost, .. } = assemble(&settings, &tiles, true);
            let cost = cost.expect("a cost image was asked for");
            let tiles_x = w.div_ceil(TILE);
            for y in 0..h {
                for x in 0..w {
                    let tile = y / TILE * tiles_x + x / TILE;
                    assert_eq!(
                        film.get(x, y),
                        Vec3::new(x as f32, y as f32, tile as f32),
                        "{w}x{h} at ({x}, {y})"
                    );
                    assert_eq!(cost[(y * w + x) as usize], y * w + x + 1);
                }
            }
            let n = u64::from(tile_count(w, h));
            assert_eq!(rays.camera, n * (n + 1) / 2, "every tile's counts are summed");
            let Assembled { cost, .. } = assemble(&settings, &labelled_tiles(w, h, false), false);
            assert!(cost.is_none());
        }
    }
}
