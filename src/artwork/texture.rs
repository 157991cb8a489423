//! Raster images as textures that ride the mesh (the paper's §3 and Fig. 2: the input images
//! are the textures of the source and target triangulations, carried to each in-between
//! triangulation piecewise-affinely and blended).
//!
//! An image is covered by a regular grid of cells in its own pixel space, its **texture grid**,
//! and every cell is cut into two triangles along the same diagonal. Each grid vertex is bound
//! to the mesh like any artwork point (barycentric coordinates in the triangle under it;
//! vertices outside the mesh follow the nearest triangle's affine map), so a frame places the
//! grid vertices, and each cell triangle maps its part of the image by the affine map taking its
//! corners in the image to their places in the frame: an [`ImagePiece`].
//!
//! Why a grid and not the mesh's own triangles: the number of pieces stays bounded whatever the
//! mesh's density ([`MAX_CELLS`] a side), which is what an animated SVG pays for per piece, and
//! the parts of an image outside the mesh are carried by the same rule as the rest. The cells
//! the SVG outputs draw are twice as long as the mesh's mean edge (at most [`MAX_CELLS`] a
//! side), and raster frames draw each of them as 4 × 4 (half the mean edge: cheap in pixels,
//! where a piece costs no bytes), so the raster grid resolves the mesh's map; where that map
//! is affine (the ends of the morph, a similarity) every grid reproduces it exactly. Where a
//! cell straddles a narrow gap between two parts of the shape that move apart, the pixels in
//! the gap are stretched across it (at most a cell wide).

use super::ImageItem;
use crate::geometry::Point;
use kurbo::Affine;
use std::sync::{Arc, OnceLock};

/// Most cells along the longer side of an image's texture grid as the SVG outputs draw it
/// (at most `2·MAX_CELLS²` pieces per image: every piece is an element with its own
/// animation, a kilobyte or two of an animated SVG); the bound grid, which raster frames draw,
/// splits each of those cells [`RASTER_SPLIT`] times a side ([`ImageGrid::pieces_every`]).
pub(crate) const MAX_CELLS: u32 = 12;

/// How many raster cells a side each SVG cell holds: raster frames pay per pixel, not per
/// piece, so they draw the finer grid.
pub(crate) const RASTER_SPLIT: u32 = 4;

/// Where an image's texture grid lies in a frame: `(columns + 1) × (rows + 1)` grid vertices,
/// row by row from the image's top-left corner, in root user space.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageGrid {
    /// Cells across the image.
    pub columns: u32,
    /// Cells down the image.
    pub rows: u32,
    /// The grid vertices placed in the frame, row-major.
    pub points: Vec<Point>,
}

/// One triangle of a texture grid: where it is in the image and where it is in the frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImagePiece {
    /// The corners in image pixels.
    pub image: [Point; 3],
    /// The same corners placed in the frame (root user space).
    pub frame: [Point; 3],
    /// The corners' indices into [`ImageGrid::points`].
    pub vertices: [usize; 3],
}

impl ImagePiece {
    /// The affine map from image pixels to root user space that takes this piece's image
    /// corners to its frame corners; `None` when either triangle is degenerate.
    pub fn transform(&self) -> Option<Affine> {
        let m = |[a, b, c]: [Point; 3]| {
            Affine::new([b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y, a.x, a.y])
        };
        let (from, to) = (m(self.image), m(self.frame));
        let det = from.determinant();
        if det == 0.0 || !det.is_finite() || !to.determinant().is_finite() {
            return None;
        }
        Some(to * from.inverse())
    }
}

impl ImageGrid {
    /// Cells across and down a grid over `img` whose cells are about `cell` user units long
    /// (twice the mesh's mean edge), at least one and at most 12 along the longer side.
    pub fn size_for(img: &ImageItem, cell: f64) -> (u32, u32) {
        let [a, b, c, d, _, _] = img.transform.as_coeffs();
        let w = img.width * a.hypot(b);
        let h = img.height * c.hypot(d);
        let count = |len: f64| {
            let n = len / cell;
            if n.is_finite() {
                n.ceil().max(1.0)
            } else {
                1.0
            }
        };
        let (mut nx, mut ny) = (count(w), count(h));
        let longest = nx.max(ny);
        if longest > MAX_CELLS as f64 {
            let k = MAX_CELLS as f64 / longest;
            nx = (nx * k).round().max(1.0);
            ny = (ny * k).round().max(1.0);
        }
        (nx as u32, ny as u32)
    }

    /// Index of grid vertex `(i, j)` (column `i`, row `j`).
    pub fn vertex(&self, i: u32, j: u32) -> usize {
        j as usize * (self.columns as usize + 1) + i as usize
    }

    /// Grid vertex `(i, j)` in the image's pixels.
    pub fn image_point(img: &ImageItem, columns: u32, rows: u32, i: u32, j: u32) -> Point {
        Point::new(
            img.width * i as f64 / columns as f64,
            img.height * j as f64 / rows as f64,
        )
    }

    /// The grid vertices of a `columns × rows` grid over `img` where the image is drawn
    /// (its `transform`), row-major: what [`ImageGrid::points`] is at rest.
    pub fn rest_points(img: &ImageItem, columns: u32, rows: u32) -> Vec<Point> {
        let mut out = Vec::with_capacity((columns as usize + 1) * (rows as usize + 1));
        for j in 0..=rows {
            for i in 0..=columns {
                let p = Self::image_point(img, columns, rows, i, j);
                let q = img.transform * kurbo::Point::new(p.x, p.y);
                out.push(Point::new(q.x, q.y));
            }
        }
        out
    }

    /// Every cell's two triangles, row by row, each cell cut along its diagonal from the
    /// top-left to the bottom-right corner.
    pub fn pieces<'a>(&'a self, img: &'a ImageItem) -> impl Iterator<Item = ImagePiece> + 'a {
        self.pieces_every(img, 1)
    }

    /// [`ImageGrid::pieces`] of the coarser grid made of every `step`-th grid line (`step`
    /// must divide both the columns and the rows; 1 is used where it does not): raster frames
    /// draw the bound grid, the SVG outputs every fourth line of it.
    pub fn pieces_every<'a>(
        &'a self,
        img: &'a ImageItem,
        step: u32,
    ) -> impl Iterator<Item = ImagePiece> + 'a {
        let s = if step > 0 && self.columns % step == 0 && self.rows % step == 0 {
            step
        } else {
            1
        };
        (0..self.rows).step_by(s as usize).flat_map(move |j| {
            (0..self.columns).step_by(s as usize).flat_map(move |i| {
                let corners = [(i, j), (i + s, j), (i + s, j + s), (i, j + s)];
                [[0, 1, 2], [0, 2, 3]].into_iter().map(move |tri| {
                    let at = tri.map(|k| corners[k]);
                    ImagePiece {
                        image: at
                            .map(|(a, b)| Self::image_point(img, self.columns, self.rows, a, b)),
                        frame: at.map(|(a, b)| self.points[self.vertex(a, b)]),
                        vertices: at.map(|(a, b)| self.vertex(a, b)),
                    }
                })
            })
        })
    }

    /// The grid vertices around the image's edge, once each, clockwise in the image (top
    /// row left to right, right column down, bottom row back, left column up).
    pub fn border(&self) -> Vec<usize> {
        let (nx, ny) = (self.columns, self.rows);
        let mut out = Vec::with_capacity(2 * (nx + ny) as usize);
        out.extend((0..nx).map(|i| self.vertex(i, 0)));
        out.extend((0..ny).map(|j| self.vertex(nx, j)));
        out.extend((1..=nx).rev().map(|i| self.vertex(i, ny)));
        out.extend((1..=ny).rev().map(|j| self.vertex(0, j)));
        out
    }

    /// Whether grid vertex `k` lies on the image's edge.
    pub fn on_border(&self, k: usize) -> bool {
        let w = self.columns as usize + 1;
        let (i, j) = (k % w, k / w);
        i == 0 || j == 0 || i == self.columns as usize || j == self.rows as usize
    }
}

/// An image's decoded pixels, ready to be sampled: premultiplied RGBA8, each texel spread to
/// the low bytes of the four 16-bit lanes of a `u64` (R, B, G, A from the bottom), so that the
/// bilinear sampling of a warped texture (§3, Fig. 2) weighs all four channels of a texel with
/// one multiplication. Twice the bytes of packed RGBA, spent once per image to save the
/// spreading of four texels in every pixel of every frame.
pub struct Texels {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// The texels row by row, each as [`Texels::spread`] makes it.
    pub lanes: Vec<u64>,
}

impl Texels {
    /// The byte lanes of a `u64` that hold a [`Texels::spread`] texel's channels.
    pub const LANES: u64 = 0x00ff_00ff_00ff_00ff;

    /// The texels of a pixmap (premultiplied RGBA8).
    pub fn from_pixmap(pixmap: &tiny_skia::Pixmap) -> Texels {
        Texels {
            width: pixmap.width(),
            height: pixmap.height(),
            lanes: pixmap
                .data()
                .chunks_exact(4)
                .map(|p| Texels::spread(u32::from_le_bytes([p[0], p[1], p[2], p[3]])))
                .collect(),
        }
    }

    /// A packed RGBA8 pixel (little-endian) with each channel in the low byte of a 16-bit
    /// lane.
    #[inline(always)]
    pub fn spread(p: u32) -> u64 {
        let p = p as u64;
        (p | p << 24) & Texels::LANES
    }

    /// The packed RGBA8 pixel of [`Texels::spread`] lanes (the inverse of `spread`).
    #[inline(always)]
    pub fn gather(q: u64) -> u32 {
        (q | q >> 24) as u32
    }
}

/// An image's decoded texels, decoded once on first use and shared by every copy of the image
/// item (warping clones items, not pixels). Equality ignores it: it is a cache of `data`, not
/// part of what the item is.
#[derive(Clone, Default)]
pub struct DecodedImage(Arc<OnceLock<Option<Arc<Texels>>>>);

impl DecodedImage {
    /// The texels, decoding them with `decode` the first time (`None`: they cannot be
    /// decoded, and the image is not drawn).
    pub fn get_or_decode(&self, decode: impl FnOnce() -> Option<Texels>) -> Option<Arc<Texels>> {
        self.0.get_or_init(|| decode().map(Arc::new)).clone()
    }
}

impl PartialEq for DecodedImage {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl std::fmt::Debug for DecodedImage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self.0.get() {
            None => "DecodedImage(not yet)",
            Some(None) => "DecodedImage(undecodable)",
            Some(Some(_)) => "DecodedImage(decoded)",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(transform: Affine) -> ImageItem {
        ImageItem {
            id: "i".into(),
            data: Arc::new(Vec::new()),
            mime: "image/png",
            width: 40.0,
            height: 20.0,
            transform,
            pixelated: false,
            grid: None,
            pixels: DecodedImage::default(),
        }
    }

    #[test]
    fn grid_size_follows_the_cell_and_is_capped() {
        let img = image(Affine::scale(2.0));
        // 80 × 40 user units.
        assert_eq!(ImageGrid::size_for(&img, 10.0), (8, 4));
        assert_eq!(ImageGrid::size_for(&img, 1e9), (1, 1));
        assert_eq!(ImageGrid::size_for(&img, 0.01), (MAX_CELLS, MAX_CELLS / 2));
        assert_eq!(ImageGrid::size_for(&img, 20.0), (4, 2));
        assert_eq!(ImageGrid::size_for(&img, f64::NAN), (1, 1));
    }

    #[test]
    fn pieces_tile_the_image_and_map_it_where_it_is_drawn() {
        let m =
            Affine::rotate(0.7).then_translate(kurbo::Vec2::new(5.0, -3.0)) * Affine::scale(1.5);
        let img = image(m);
        let grid = ImageGrid {
            columns: 3,
            rows: 2,
            points: ImageGrid::rest_points(&img, 3, 2),
        };
        let pieces: Vec<_> = grid.pieces(&img).collect();
        assert_eq!(pieces.len(), 12);
        let area: f64 = pieces
            .iter()
            .map(|p| {
                let [a, b, c] = p.image;
                0.5 * (b - a).perp_dot(c - a).abs()
            })
            .sum();
        assert!((area - 800.0).abs() < 1e-9);
        for p in &pieces {
            let t = p.transform().unwrap();
            for (a, b) in t.as_coeffs().iter().zip(m.as_coeffs()) {
                assert!((a - b).abs() < 1e-9, "{t:?} vs {m:?}");
            }
        }
        let border = grid.border();
        assert_eq!(border.len(), 10);
        // Every second grid line: 3 × 2 cells do not halve, so the grid is kept.
        assert_eq!(grid.pieces_every(&img, 2).count(), 12);
        let fine = ImageGrid {
            columns: 4,
            rows: 2,
            points: ImageGrid::rest_points(&img, 4, 2),
        };
        let coarse: Vec<_> = fine.pieces_every(&img, 2).collect();
        assert_eq!(coarse.len(), 4);
        assert_eq!(coarse[1].image[1], Point::new(20.0, 20.0));
        assert!(border.iter().all(|&k| grid.on_border(k)));
        assert!(!grid.on_border(grid.vertex(1, 1)));
    }
}
