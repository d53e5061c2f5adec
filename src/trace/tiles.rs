//! Tiles: the image cut into squares of [`TILE`] pixels, shaded in parallel, each written into
//! its own pixels of the film (noise-driven renders assemble theirs in tile order at the end),
//! so the film does not depend on which thread shaded what.

use rayon::iter::Either;
use rayon::prelude::*;
use smallvec::SmallVec;

use super::finite::DropTally;
use super::settings::RenderSettings;
use super::stats::RayCounts;

use crate::film::Film;
use crate::math::Vec3;
use crate::sample::adaptive::AdaptiveStats;

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

/// Runs `shade` over every tile (`[x0, y0, x1, y1]`, ends exclusive), tiles in parallel, each
/// writing its pixels (and its costs when `want_cost`: every tile then reports costs) straight
/// into the film (and the cost image) through its `TileView`; the counts are summed as tiles
/// finish (the sums do not depend on the order).
///
/// Writing in place replaced tiles returning their pixels to be copied into the film once all
/// were done: that copy (with the film's first-touch page faults) was 1.1-1.3 ms of a 30 ms
/// trace of a 640×480 frame on 2 threads, a serial-looking tail after the last tile
/// (measured on the spheres' twin). Here each tile's copy is of pixels it has just shaded.
pub(super) fn render_tiles<F>(
    settings: &RenderSettings,
    want_cost: bool,
    shade: F,
    tile_done: &(dyn Fn() + Sync),
) -> Assembled
where
    F: Fn([u32; 4], &mut RayCounts, &mut TileOut) + Sync,
{
    let shade = |area: [u32; 4], rays: &mut RayCounts, out: &mut TileOut, _: &mut ()| shade(area, rays, out);
    render_tiles_with(settings, want_cost, shade, tile_done).0
}

/// Figures a tile's shader keeps besides its ray counts (an adaptive render's
/// [`AdaptiveStats`]), summed over the tiles; their sums must not depend on the order.
pub(super) trait TileFigures: Default + Send {
    /// The figures of two sets of tiles together.
    fn and(self, other: Self) -> Self;
}

impl TileFigures for () {
    fn and(self, (): ()) {}
}

impl TileFigures for AdaptiveStats {
    fn and(self, other: Self) -> Self {
        self + other
    }
}

/// [`render_tiles`] for a shader that also keeps figures of its own (`X`): their sum over the
/// tiles comes back with the image.
pub(super) fn render_tiles_with<F, X>(
    settings: &RenderSettings,
    want_cost: bool,
    shade: F,
    tile_done: &(dyn Fn() + Sync),
) -> (Assembled, X)
where
    F: Fn([u32; 4], &mut RayCounts, &mut TileOut, &mut X) + Sync,
    X: TileFigures,
{
    let (w, h) = (settings.width, settings.height);
    let band = (TILE * w) as usize;
    let mut film = Film::new(w, h);
    let mut cost = want_cost.then(|| vec![0u32; w as usize * h as usize]);
    let cost_bands = match cost.as_deref_mut() {
        Some(cost) => Either::Left(cost.par_chunks_mut(band).map(Some)),
        None => Either::Right((0..h.div_ceil(TILE)).into_par_iter().map(|_| None)),
    };
    let shade = &shade;
    // Counts are integers and drops keep the lowest pixel indices: their sums do not depend on
    // the order tiles finish in, so they are added as they come (a tile's `RayCounts` holds two
    // 96-bucket histograms: collected per tile they were 6 B a pixel).
    let (rays, dropped, figures) = film
        .pixels
        .par_chunks_mut(band)
        .zip(cost_bands)
        .enumerate()
        .flat_map(|(by, (colours, costs))| {
            TileView::band(colours, costs, w)
                .into_par_iter()
                // One tile per job. Left to split the range as it likes, rayon ran a frame's
                // last stretch of tiles (a hundred or more) as one job on one thread while the
                // other waited: 6-8 ms of a 75 ms trace on the 100k spheres' twin (perf, 2
                // threads). A tile is tens to hundreds of microseconds of work; a job costs
                // about one.
                .with_max_len(1)
                .enumerate()
                .map(move |(bx, mut view)| {
                    let (x0, y0) = (bx as u32 * TILE, by as u32 * TILE);
                    let area = [x0, y0, (x0 + TILE).min(w), (y0 + TILE).min(h)];
                    let mut rays = RayCounts::default();
                    let mut figures = X::default();
                    let mut out =
                        TileOut { pixels: Vec::with_capacity((TILE * TILE) as usize), costs: Vec::new() };
                    crate::simd::with_single_ray_level(settings.simd, || {
                        shade(area, &mut rays, &mut out, &mut figures)
                    });
                    let dropped = view.fill(&out, area, w);
                    tile_done();
                    (rays, dropped, figures)
                })
        })
        .reduce(
            || (RayCounts::default(), DropTally::default(), X::default()),
            |(mut rays, mut dropped, figures), (more_rays, more_dropped, more_figures)| {
                rays.add(&more_rays);
                dropped.add(&more_dropped);
                (rays, dropped, figures.and(more_figures))
            },
        );
    // Every path (fixed samples or adaptive) reaches the film finite by construction.
    debug_assert!(
        film.pixels.iter().all(|c| c.is_finite()),
        "non-finite radiance at pixel index {:?}",
        film.pixels.iter().position(|c| !c.is_finite())
    );
    (Assembled { film, rays, cost, dropped }, figures)
}

/// One tile's part of the film: its rows of colours and (when a cost image is wanted) of
/// costs, top to bottom, each [`TILE`] wide but at the right edge.
#[derive(Default)]
struct TileView<'a> {
    colours: SmallVec<[&'a mut [Vec3]; TILE as usize]>,
    costs: SmallVec<[&'a mut [u32]; TILE as usize]>,
}

impl<'a> TileView<'a> {
    /// The views of the tiles of one band of rows of an image `width` pixels wide (`colours`,
    /// and `costs` when wanted: [`TILE`] rows, fewer at the bottom), left to right.
    fn band(colours: &'a mut [Vec3], costs: Option<&'a mut [u32]>, width: u32) -> Vec<Self> {
        let (w, tile) = (width as usize, TILE as usize);
        let mut views: Vec<Self> = (0..w.div_ceil(tile)).map(|_| Self::default()).collect();
        for row in colours.chunks_mut(w) {
            for (view, part) in views.iter_mut().zip(row.chunks_mut(tile)) {
                view.colours.push(part);
            }
        }
        for row in costs.into_iter().flat_map(|costs| costs.chunks_mut(w)) {
            for (view, part) in views.iter_mut().zip(row.chunks_mut(tile)) {
                view.costs.push(part);
            }
        }
        views
    }

    /// Writes what the tile's shader wrote (`out`, row-major over `area`) into the film (and
    /// the cost image, when this view has one); the samples its pixels dropped, by row-major
    /// index in an image `width` pixels wide.
    fn fill(&mut self, out: &TileOut, [x0, y0, x1, y1]: [u32; 4], width: u32) -> DropTally {
        let tw = (x1 - x0) as usize;
        debug_assert_eq!(out.pixels.len(), tw * (y1 - y0) as usize, "one entry per pixel");
        debug_assert_eq!(self.colours.len(), (y1 - y0) as usize, "one slice per row");
        let mut dropped = DropTally::default();
        for ((y, row), shaded) in (y0..).zip(&mut self.colours).zip(out.pixels.chunks(tw)) {
            for ((x, pixel), &(colour, n)) in (x0..).zip(row.iter_mut()).zip(shaded) {
                *pixel = colour;
                dropped.record(y * width + x, n);
            }
        }
        if !self.costs.is_empty() {
            debug_assert_eq!(out.costs.len(), out.pixels.len(), "a cost per pixel");
            for (row, costs) in self.costs.iter_mut().zip(out.costs.chunks(tw)) {
                row.copy_from_slice(costs);
            }
        }
        dropped
    }
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
    fn tiles_write_every_pixel_and_cost_in_place() {
        for (w, h) in [(37, 21), (16, 16), (1, 40), (50, 1), (33, 17)] {
            for want_cost in [false, true] {
                let settings = RenderSettings { width: w, height: h, ..RenderSettings::default() };
                // Each pixel's colour is its coordinates and its tile's origin; its cost and
                // its dropped samples come from its index (every seventh pixel drops some).
                let shade = |[x0, y0, x1, y1]: [u32; 4], rays: &mut RayCounts, out: &mut TileOut| {
                    rays.camera += 1;
                    for y in y0..y1 {
                        for x in x0..x1 {
                            let i = y * w + x;
                            let dropped = if i % 7 == 3 { i % 5 + 1 } else { 0 };
                            out.pixels
                                .push((Vec3::new(x as f32, y as f32, (x0 + 1000 * y0) as f32), dropped));
                            if want_cost {
                                out.costs.push(i + 1);
                            }
                        }
                    }
                };
                let done = std::sync::atomic::AtomicU32::new(0);
                let tile_done = || {
                    done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                };
                let Assembled { film, rays, cost, dropped } =
                    render_tiles(&settings, want_cost, shade, &tile_done);
                for y in 0..h {
                    for x in 0..w {
                        let origin = (x / TILE * TILE + 1000 * (y / TILE * TILE)) as f32;
                        assert_eq!(
                            film.get(x, y),
                            Vec3::new(x as f32, y as f32, origin),
                            "{w}x{h} at ({x}, {y})"
                        );
                    }
                }
                let tiles = tile_count(w, h);
                assert_eq!(done.into_inner(), tiles, "every tile reported done");
                assert_eq!(rays.camera, u64::from(tiles), "every tile's counts are summed");
                match cost {
                    Some(cost) => assert!(want_cost && (0..w * h).all(|i| cost[i as usize] == i + 1)),
                    None => assert!(!want_cost),
                }
                let expected: Vec<u32> = (0..w * h).filter(|i| i % 7 == 3).collect();
                let mut brute = DropTally::default();
                for &i in &expected {
                    brute.record(i, i % 5 + 1);
                }
                let found = dropped.finish(w);
                assert_eq!(found, brute.finish(w), "{w}x{h}");
                assert_eq!(found.pixels, expected.len() as u64);
            }
        }
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
