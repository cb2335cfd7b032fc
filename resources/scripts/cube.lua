-- The seed's Cube.lua: a cube open on one side (the front, z = 0), drawn with strokes.
-- Run it with `cube.lua` in the console; `undo` takes the strokes back one by one, then the `new`.
local n = 32
cmd.new(n, n, n)
local function face(axis, index, r, g, b)
  for v = 0, n - 1 do
    cmd.stroke(axis, index, 1, r, g, b, 255, 0, v, n - 1, v)
  end
end
face("x", 0, 220, 60, 50)       -- left
face("x", n - 1, 60, 200, 80)   -- right
face("y", 0, 230, 230, 230)     -- top
face("y", n - 1, 180, 180, 180) -- bottom
face("z", n - 1, 70, 110, 230)  -- back; the front stays open
print("cube.lua: a " .. n .. "^3 cube, open at the front")
