#pragma once
// Demodulation (Schied et al. 2017, sec. 4): the filters smooth illumination, not radiance, so that
// texture detail carried by the albedo stays sharp; emission seen directly is lit by nothing and is
// neither demodulated nor filtered.
#include "denoise/guides.h"
#include "denoise/planes.h"
#include "engine/frame_stats.h"
#include "engine/gbuffer.h"
#include "engine/image.h"

namespace candela {

// Albedo channels below this are raised to it before dividing (black surfaces would divide by zero);
// remodulation multiplies by the same value, so the round trip is exact.
inline constexpr float kMinAlbedo = 0.01f;

// Stage "denoise_demodulate": reads the noisy radiance, the G-buffer's albedo and emission and the
// guides' filtered mask; writes `illumination` = (L - Le) / max(albedo, kMinAlbedo) at filtered pixels,
// the radiance L itself at the other hits (emitter borders, which only SVGF's temporal accumulation
// touches), 0 elsewhere (non-finite radiance becomes 0 and is counted in `non_finite`). One pass, O(pixels).
void demodulate(const Image& noisy, const GBuffer& g, const Guides& guides, ColorPlanes& illumination,
                Counter& non_finite);

// Stage "denoise_remodulate": reads the filtered illumination, the G-buffer, the guides' filtered mask
// and the noisy radiance; writes `out` (resized only when its size differs, so that a frame loop reuses
// its pixels) = filtered * max(albedo, kMinAlbedo) + Le at filtered pixels, `filtered` itself at the other
// hits (radiance, see demodulate) and the noisy radiance where nothing was hit (background). One pass,
// O(pixels).
void remodulate(const ColorPlanes& filtered, const GBuffer& g, const Guides& guides, const Image& noisy, Image& out);

// The shared start of every denoiser's frame, timed as stages "denoise_guides" and "denoise_demodulate";
// with_albedo: the guides carry albedo planes (the bilateral filter's range term).
void prepare_frame(const GBuffer& g, const Image& noisy, bool with_albedo, Guides& guides, ColorPlanes& illumination,
                   FrameStats& stats);

}  // namespace candela
