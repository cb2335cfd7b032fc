"""The physical sky's lookup tables on the GPU (Hillaire 2020): transmittance (256 x 64) and multiple scattering
(32 x 32), which depend on the atmosphere only, and the sky seen from the camera (192 x 108), which depends on the
camera's altitude and the sun's elevation too; each is recomputed only when what it depends on changes (counted
in `computed`: looking around recomputes none, the sun's azimuth neither). The clouds' passes read all three from
one atlas texture, so the tables take one texture unit of theirs.

The passes here bind what they read from their own units before the cloud renderer binds anything for its frame
(CloudRenderer.render updates the tables first), so they need no unit of the cloud renderer's allocator."""
from __future__ import annotations

import math

import moderngl

from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.model.clouds import atmosphere as am
from app.model.clouds.atmosphere import Atmosphere

# Where each table lies in the atlas: (x, y, width, height) in texels.
REGIONS = {"transmittance": (0, 0, *am.TRANSMITTANCE_SIZE),
           "multiscatter": (0, am.TRANSMITTANCE_SIZE[1], *am.MULTISCATTER_SIZE),
           "sky_view": (am.MULTISCATTER_SIZE[0], am.TRANSMITTANCE_SIZE[1], *am.SKY_VIEW_SIZE)}
ATLAS_SIZE = (max(x + w for x, _y, w, _h in REGIONS.values()), max(y + h for _x, y, _w, h in REGIONS.values()))


def medium_uniforms(atm: Atmosphere) -> dict:
    """The atmosphere's uniforms (resources/shaders/atmosphere.shl)."""
    return dict(u_bottom_radius=atm.bottom, u_top_radius=atm.top, u_rayleigh_scattering=atm.rayleigh_scattering,
                u_rayleigh_height=atm.rayleigh_height, u_mie_scattering=atm.mie_scattering,
                u_mie_extinction=atm.mie_extinction, u_mie_height=atm.mie_height, u_mie_g=atm.mie_g,
                u_ozone_absorption=atm.ozone_absorption, u_ozone_centre=atm.ozone_centre,
                u_ozone_width=atm.ozone_width, u_sun_radius=math.radians(atm.sun_radius_deg))


def camera_radius(atm: Atmosphere, altitude: float) -> float:
    return atm.bottom + max(altitude, am.MIN_ALTITUDE)


class AtmosphereTables:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self.units = TextureUnits()
        self._screen = VertexArrays(lambda program: ctx.vertex_array(program, []))
        self.tables = {name: self._texture(size) for name, size in (("transmittance", am.TRANSMITTANCE_SIZE),
                                                                     ("multiscatter", am.MULTISCATTER_SIZE),
                                                                     ("sky_view", am.SKY_VIEW_SIZE))}
        self.atlas = self._texture(ATLAS_SIZE)
        self._fbos = {name: ctx.framebuffer([t]) for name, t in {**self.tables, "atlas": self.atlas}.items()}
        self.computed = {name: 0 for name in self.tables}
        self._keys: dict[str, tuple] = {}

    def _texture(self, size) -> moderngl.Texture:
        t = self.ctx.texture(size, 4, dtype="f4")
        t.filter = (moderngl.LINEAR, moderngl.LINEAR)
        t.repeat_x = t.repeat_y = False
        return t

    def update(self, atm: Atmosphere, altitude: float, sun_y: float, multiple: bool = True) -> None:
        """Recompute the tables whose inputs changed (`multiple` False: the sky of single scattering alone, for
        the tests), each after those it reads, then the atlas."""
        radius = camera_radius(atm, altitude)
        keys = {"transmittance": (atm,), "multiscatter": (atm,), "sky_view": (atm, radius, sun_y, multiple)}
        stale = [name for name, key in keys.items() if self._keys.get(name) != key]
        if not stale:
            return
        stale = list(keys)[list(keys).index(stale[0]):]  # a table's readers follow it
        tables = self.tables
        own = {"transmittance": lambda: dict(u_transmittance_steps=am.TRANSMITTANCE_STEPS),
               "multiscatter": lambda: dict(u_multiscatter_steps=am.MULTISCATTER_STEPS,
                                            u_multiscatter_directions=am.MULTISCATTER_DIRECTIONS,
                                            u_ground_albedo=atm.ground_albedo,
                                            **self.units.bind(u_transmittance=tables["transmittance"])),
               "sky_view": lambda: dict(u_camera_radius=radius, u_sun_mu=sun_y, u_sky_view_steps=am.SKY_VIEW_STEPS,
                                        u_multiple=int(multiple),
                                        **self.units.bind(u_transmittance=tables["transmittance"],
                                                          u_multiscatter=tables["multiscatter"]))}
        medium = medium_uniforms(atm)
        for name in stale:
            self._draw(f"atmosphere_{name}", self._fbos[name], medium, own[name]())
            self._keys[name] = keys[name]
            self.computed[name] += 1
        regions = {f"u_{name}_region": tuple(map(float, r)) for name, r in REGIONS.items()}
        self._draw("atmosphere_pack", self._fbos["atlas"], {}, dict(**regions, **self.units.bind(
            u_transmittance=tables["transmittance"], u_multiscatter=tables["multiscatter"],
            u_sky_view=tables["sky_view"])))

    def _draw(self, program_name: str, fbo, medium: dict, own: dict) -> None:
        program = self.shaders.program(program_name)
        set_uniforms(program, medium, optional=medium.keys())
        set_uniforms(program, own)
        fbo.use()
        self._screen.get(program).render(moderngl.TRIANGLES, vertices=3)

    def uniforms(self, atm: Atmosphere) -> dict:
        """What the clouds' passes read of the atmosphere, but the atlas's sampler: the medium, the atlas's
        regions, and the sun's disc."""
        regions = {f"u_atlas_{name}": tuple(map(float, r)) for name, r in REGIONS.items()}
        return dict(**medium_uniforms(atm), **regions, u_atlas_size=tuple(map(float, ATLAS_SIZE)),
                    u_aerial_steps=am.AERIAL_STEPS, u_sun_cos_radius=math.cos(math.radians(atm.sun_radius_deg)))
