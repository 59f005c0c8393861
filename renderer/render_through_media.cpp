// The render loop's body with the volumetric integrator (renderer/render_tile.h says why it is
// compiled here, apart from the surface integrator's).
#include "renderer/render_tile.h"
#include "renderer/volumetric_path_integrator.h"

namespace penumbra::detail {

template <TraversalBackend Accel>
TileResult renderTileThroughMedia(const Accel& accel, const Scene& scene, const Camera& camera,
                                  const IntegratorContext& ctx, const PixelWindow& tile, uint32_t firstSample,
                                  uint32_t endSample, uint32_t frozenDims, bool sceneMoves,
                                  const ActivePixels* active, Film& film) {
    return renderTile<true>(accel, scene, camera, ctx, tile, firstSample, endSample, frozenDims, sceneMoves,
                            active, film);
}

template TileResult renderTileThroughMedia(const EmbreeAccelerator&, const Scene&, const Camera&,
                                           const IntegratorContext&, const PixelWindow&, uint32_t, uint32_t,
                                           uint32_t, bool, const ActivePixels*, Film&);
template TileResult renderTileThroughMedia(const BvhAccelerator&, const Scene&, const Camera&,
                                           const IntegratorContext&, const PixelWindow&, uint32_t, uint32_t,
                                           uint32_t, bool, const ActivePixels*, Film&);

}  // namespace penumbra::detail
