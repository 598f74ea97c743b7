//! egui's texture copies waiting for a frame ([`Upload`]), kept disjoint per texture
//! ([`queue`]): where a later upload overlaps a pending one, its texels are written into the
//! pending one's and only the rest is added. One frame's copies into an image then write
//! disjoint texels, and need no order among themselves — the overlay's upload pass records
//! them with no barrier between them (`render/passes/overlay.rs`).

use ash::vk;
use egui::TextureId;

/// Texels waiting to be copied into a texture by the next frame that draws the overlay. The
/// pending uploads of one texture never overlap (`queue`): one frame's copies into an image
/// write disjoint texels, so they need no order among themselves.
#[derive(Clone, Debug, PartialEq)]
pub struct Upload {
    /// The texture (looked up when the copy is staged: the image may have been replaced since).
    pub id: TextureId,
    /// Top-left texel of the region.
    pub origin: [u32; 2],
    /// Size of the region.
    pub extent: vk::Extent2D,
    /// RGBA8 texels, rows tightly packed.
    pub texels: Vec<u8>,
}

/// A region in texels: [x0, y0, x1, y1), x1 > x0 and y1 > y0.
type Rect = [u32; 4];

impl Upload {
    fn rect(&self) -> Rect {
        let [x, y] = self.origin;
        [x, y, x + self.extent.width, y + self.extent.height]
    }

    /// Where in `texels` the texel at texture coordinates (x, y) starts (inside the region).
    fn offset(&self, x: u32, y: u32) -> usize {
        4 * ((y - self.origin[1]) as usize * self.extent.width as usize + (x - self.origin[0]) as usize)
    }

    /// The part of the region inside `rect` (which lies inside it), with its texels.
    fn crop(&self, rect: Rect) -> Upload {
        let [x0, y0, x1, y1] = rect;
        let row = 4 * (x1 - x0) as usize;
        let mut texels = Vec::with_capacity(row * (y1 - y0) as usize);
        for y in y0..y1 {
            let start = self.offset(x0, y);
            texels.extend_from_slice(&self.texels[start..start + row]);
        }
        Upload { id: self.id, origin: [x0, y0], extent: vk::Extent2D { width: x1 - x0, height: y1 - y0 }, texels }
    }

    /// Write `later`'s texels inside `rect` (in both regions) over this region's.
    fn overwrite(&mut self, later: &Upload, rect: Rect) {
        let [x0, y0, x1, _] = rect;
        let row = 4 * (x1 - x0) as usize;
        for y in y0..rect[3] {
            let (to, from) = (self.offset(x0, y), later.offset(x0, y));
            self.texels[to..to + row].copy_from_slice(&later.texels[from..from + row]);
        }
    }
}

/// Where `a` and `b` overlap, if they do.
fn overlap(a: Rect, b: Rect) -> Option<Rect> {
    let r = [a[0].max(b[0]), a[1].max(b[1]), a[2].min(b[2]), a[3].min(b[3])];
    (r[0] < r[2] && r[1] < r[3]).then_some(r)
}

/// `outer` without `inner` (inside it): the bands above and below it, and either side of it.
fn around(outer: Rect, inner: Rect) -> impl Iterator<Item = Rect> {
    let [ox0, oy0, ox1, oy1] = outer;
    let [ix0, iy0, ix1, iy1] = inner;
    [[ox0, oy0, ox1, iy0], [ox0, iy1, ox1, oy1], [ox0, iy0, ix0, iy1], [ix1, iy0, ox1, iy1]]
        .into_iter()
        .filter(|r| r[0] < r[2] && r[1] < r[3])
}

/// Add `upload` to `uploads`, the pending copies of every texture, keeping each texture's
/// disjoint: where it overlaps a pending region of its texture, its texels are written into
/// that region's (the later texels win, as the copies in egui's order would have it), and only
/// the rest is added, as rectangles around each overlap. Without this, a texture set whole and
/// patched before a frame draws — egui's font after `Viewer::replace_renderer` resends it,
/// patched with the frame's new glyphs — would be copied twice into the same texels by one
/// pass, with no barrier between the copies (a write-after-write hazard).
pub fn queue(uploads: &mut Vec<Upload>, upload: Upload) {
    let id = upload.id;
    let mut pieces = vec![upload];
    for pending in uploads.iter_mut().filter(|u| u.id == id) {
        let mut rest = Vec::with_capacity(pieces.len());
        for piece in pieces {
            match overlap(pending.rect(), piece.rect()) {
                Some(shared) => {
                    pending.overwrite(&piece, shared);
                    rest.extend(around(piece.rect(), shared).map(|r| piece.crop(r)));
                }
                None => rest.push(piece),
            }
        }
        pieces = rest;
        if pieces.is_empty() {
            return;
        }
    }
    uploads.extend(pieces);
}

#[cfg(test)]
mod tests {
    use super::*;

    const FONT: TextureId = TextureId::Managed(0);

    /// An upload of `width`×`height` texels at (x, y), every texel `value`.
    fn region(id: TextureId, [x, y]: [u32; 2], [width, height]: [u32; 2], value: u8) -> Upload {
        let texels = vec![value; 4 * (width * height) as usize];
        Upload { id, origin: [x, y], extent: vk::Extent2D { width, height }, texels }
    }

    /// `uploads` copied in the order given into a `side`² RGBA8 image of `id`.
    fn paint(uploads: &[Upload], id: TextureId, side: u32) -> Vec<u8> {
        let mut image = vec![0u8; 4 * (side * side) as usize];
        for u in uploads.iter().filter(|u| u.id == id) {
            for y in 0..u.extent.height {
                for x in 0..u.extent.width {
                    let to = 4 * ((u.origin[1] + y) * side + u.origin[0] + x) as usize;
                    let from = u.offset(u.origin[0] + x, u.origin[1] + y);
                    image[to..to + 4].copy_from_slice(&u.texels[from..from + 4]);
                }
            }
        }
        image
    }

    #[test]
    fn a_patch_of_a_pending_whole_texture_is_written_into_its_texels() {
        // The font resent whole after a renderer replacement, then the frame's new glyphs.
        let mut uploads = Vec::new();
        queue(&mut uploads, region(FONT, [0, 0], [8, 8], 1));
        queue(&mut uploads, region(FONT, [2, 3], [4, 2], 2));
        assert_eq!(uploads.len(), 1, "one copy into the font");
        let texel = |x: usize, y: usize| uploads[0].texels[4 * (y * 8 + x)];
        assert_eq!((texel(2, 3), texel(5, 4), texel(6, 4), texel(2, 5)), (2, 2, 1, 1));
        // Another texture's pending copy is left alone.
        queue(&mut uploads, region(TextureId::User(1), [0, 0], [4, 4], 3));
        assert_eq!(uploads.len(), 2);
    }

    #[test]
    fn pending_uploads_stay_disjoint_and_paint_what_egui_s_order_paints() {
        let mut rng = crate::scene::rng::Rng::new(7);
        let mut below = |n: u32| (rng.next_u64() % u64::from(n)) as u32;
        for round in 0..200 {
            let (mut queued, mut sent) = (Vec::new(), Vec::new());
            for value in 1..=6u8 {
                let (x, y) = (below(16), below(16));
                let size = [1 + below(16 - x), 1 + below(16 - y)];
                let upload = region(FONT, [x, y], size, value + 10 * (round % 20) as u8);
                sent.push(upload.clone());
                queue(&mut queued, upload);
            }
            for (i, a) in queued.iter().enumerate() {
                for b in &queued[i + 1..] {
                    assert_eq!(overlap(a.rect(), b.rect()), None, "round {round}: {a:?} overlaps {b:?}");
                }
            }
            let in_order = paint(&sent, FONT, 16);
            queued.reverse();
            assert_eq!(paint(&queued, FONT, 16), in_order, "round {round}: the copies' order mattered");
        }
    }
}
