#pragma once
// What the viewer can show of a frame: the radiance (as `candela render` writes it to PNG) or a debug view
// of one G-buffer plane or of the ReSTIR DI reservoirs, and the conversion to the 8-bit pixels displayed.
#include "apps/renderer.h"
#include "apps/viewer/frame_display.h"

namespace candela {

enum class DisplayView { Radiance, Albedo, Normal, Depth, Motion, ReservoirM, ReservoirW };
inline constexpr DisplayView kDisplayViews[] = {DisplayView::Radiance,  DisplayView::Albedo, DisplayView::Normal,
                                                DisplayView::Depth,     DisplayView::Motion, DisplayView::ReservoirM,
                                                DisplayView::ReservoirW};
const char* display_view_name(DisplayView view);    // as the HUD labels it ("reservoir M")
const char* display_view_option(DisplayView view);  // as the command line names it ("reservoir-m")
// Reservoir views exist only when the renderer runs ReSTIR DI.
bool display_view_available(DisplayView view, const Renderer& renderer);
// Radiance and W are shown tonemapped (ACES + sRGB, like PNG output); the other views hold values in [0, 1].
bool display_view_tonemapped(DisplayView view);

// The view as a linear image of the render's size: radiance: Renderer::image(); albedo: base colour;
// normal: n * 0.5 + 0.5; depth: linear depth over the farthest hit's; motion: 0.5 + motion / 16 pixels
// (red x, green y); M: reservoir M over the frame's largest M; W: contribution weight. Background
// pixels are black in the G-buffer and reservoir views. Cost: one pass over the planes.
Image display_view_image(const Renderer& renderer, DisplayView view);

// 8-bit display pixels: tonemap_srgb(value, exposure) for tonemapped views, else the value clamped to
// [0, 1]; rounded to nearest as write_image does, so a radiance frame matches `candela render`'s PNG.
// Parallel over rows.
Rgba8Image to_display_pixels(const Image& image, bool tonemap, float exposure);

}  // namespace candela
