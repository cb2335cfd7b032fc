"""Texture units handed out by name, one allocator per renderer.

Each unit is named by the sampler uniform that reads it (`u_clouds`), so the texture bound there and the
uniform's value come from one place: the same name gets the same unit every time, two names never share one.
A renderer binds some textures once a frame and more per pass (the clouds' noise, then each pass's buffers), so
a pass's unit must never be one a sampler of another pass still reads; one allocator over all the renderer's
samplers (its helpers given the same one) rules that out. Renderers need no units apart from one another: each
binds what it reads before it draws."""
from __future__ import annotations

# Units a fragment shader may read in GL 3.3 (GL_MAX_TEXTURE_IMAGE_UNITS is at least this), and those whose
# sampler objects the host's debug mode checks (app/gl/core/gl_state.py).
LIMIT = 16


class TextureUnits:
    def __init__(self) -> None:
        self._units: dict[str, int] = {}

    def __getitem__(self, name: str) -> int:
        """The unit of the sampler uniform `name`, given it the first time it is asked for."""
        unit = self._units.get(name)
        if unit is None:
            if len(self._units) == LIMIT:
                raise RuntimeError(f"no texture unit left for {name!r}: all {LIMIT} are named "
                                   f"({', '.join(self._units)})")
            unit = self._units[name] = len(self._units)
        return unit

    def __contains__(self, name: str) -> bool:
        return name in self._units

    def uniforms(self, *names: str) -> dict[str, int]:
        """The values of these sampler uniforms: their units."""
        return {name: self[name] for name in names}

    def bind(self, **textures) -> dict[str, int]:
        """Bind each texture (or anything with moderngl's `use(location)`: a sampler object) at the unit of its
        sampler uniform; returns those uniforms' values, to set with the others."""
        for name, texture in textures.items():
            texture.use(self[name])
        return self.uniforms(*textures)
