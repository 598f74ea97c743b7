//! The drawing surface of the charts: an RGB bitmap whose text is laid out with the embedded
//! DejaVu Sans through `ab_glyph`.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::prelude::*;
use plotters::style::register_font;
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendTextStyle, DrawingErrorKind};

use super::FONT;
use crate::error::{Error, Result};

/// The embedded DejaVu Sans, parsed once and registered with plotters as its `sans-serif` family
/// (so plotters' own text metrics agree with [`Canvas`], which does the drawing).
pub(super) fn font() -> Result<&'static FontRef<'static>> {
    static FONT_REF: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    static DEJAVU: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
    FONT_REF
        .get_or_init(|| {
            register_font(FONT, FontStyle::Normal, DEJAVU).ok()?;
            FontRef::try_from_slice(DEJAVU).ok()
        })
        .as_ref()
        .ok_or_else(|| Error::Plot("the embedded DejaVu Sans font failed to load".into()))
}

/// A [`BitMapBackend`] whose text is laid out and rasterised here with `ab_glyph`: plotters
/// 0.3.7's own `ab_glyph` text path drops glyph side bearings and misplaces the baseline, which
/// gives uneven letter spacing and clips top-anchored text.
pub(super) struct Canvas<'a> {
    pub(super) inner: BitMapBackend<'a>,
    pub(super) font: &'static FontRef<'static>,
}

pub(super) type CanvasResult<T = ()> =
    std::result::Result<T, DrawingErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

impl DrawingBackend for Canvas<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }
    fn ensure_prepared(&mut self) -> CanvasResult {
        self.inner.ensure_prepared()
    }
    fn present(&mut self) -> CanvasResult {
        self.inner.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> CanvasResult {
        self.inner.draw_pixel(point, color)
    }
    fn draw_line<S: plotters_backend::BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> CanvasResult {
        self.inner.draw_line(from, to, style)
    }
    fn draw_rect<S: plotters_backend::BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        style: &S,
        fill: bool,
    ) -> CanvasResult {
        self.inner.draw_rect(a, b, style, fill)
    }
    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> CanvasResult {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<T: BackendTextStyle>(&self, text: &str, style: &T) -> CanvasResult<(u32, u32)> {
        let (w, h) = measure(self.font, text, style.size());
        Ok((w.ceil() as u32, h.ceil() as u32))
    }

    fn draw_text<T: BackendTextStyle>(&mut self, text: &str, style: &T, pos: BackendCoord) -> CanvasResult {
        let (colour, transform, anchor) = (style.color(), style.transform(), style.anchor());
        let (w, h) = measure(self.font, text, style.size());
        let font = self.font.as_scaled(style.size() as f32);
        // Box origin relative to the anchor, whole pixels so glyph edges stay crisp.
        let x0 = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => (-w / 2.0).round(),
            HPos::Right => -w.round(),
        };
        let y0 = match anchor.v_pos {
            VPos::Top => 0.0,
            VPos::Center => (-h / 2.0).round(),
            VPos::Bottom => -h.round(),
        };
        let (mut pen, baseline) = (x0, y0 + font.ascent().round());
        let mut prev = None;
        let mut result = Ok(());
        for c in text.chars() {
            let id = font.glyph_id(c);
            pen += prev.map_or(0.0, |p| font.kern(p, id));
            prev = Some(id);
            let glyph = id.with_scale_and_position(font.scale(), ab_glyph::point(pen, baseline));
            pen += font.h_advance(id);
            let Some(outline) = font.outline_glyph(glyph) else { continue };
            let min = outline.px_bounds().min;
            outline.draw(|gx, gy, coverage| {
                if result.is_ok() && coverage > 0.0 {
                    let (dx, dy) = transform.transform(min.x as i32 + gx as i32, min.y as i32 + gy as i32);
                    let alpha = colour.alpha * f64::from(coverage.min(1.0));
                    result = self.inner.draw_pixel((pos.0 + dx, pos.1 + dy), BackendColor { alpha, rgb: colour.rgb });
                }
            });
        }
        result
    }
}

/// Width of `text` and the font's line height (ascent − descent) at `size` pixels.
pub(super) fn measure(font: &FontRef<'static>, text: &str, size: f64) -> (f32, f32) {
    let font = font.as_scaled(size as f32);
    let mut prev = None;
    let width = text.chars().fold(0.0, |w, c| {
        let id = font.glyph_id(c);
        let kern = prev.map_or(0.0, |p| font.kern(p, id));
        prev = Some(id);
        w + kern + font.h_advance(id)
    });
    (width, font.ascent() - font.descent())
}

/// Pixel width of the widest of `texts` at `size` pixels (for sizing label areas and legends).
pub(super) fn text_width<'t>(texts: impl IntoIterator<Item = &'t str>, size: f64) -> f64 {
    let width = |t: &str| font().map_or(0.6 * size * t.chars().count() as f64, |f| f64::from(measure(f, t, size).0));
    texts.into_iter().map(width).fold(0.0, f64::max)
}
