-- A ring of snowflakes around a large one: `lua ring.lua`, or just `ring.lua`.
-- The API: cmd.<command>(args...), exec("console line"), cvar.<name>, print(...).
local count = 12
cmd.snow.clear()
cmd.snow.add(0, 0, 0.5)
for i = 0, count - 1 do
  local a = 2 * math.pi * i / count
  cmd.snow.add(0.95 * math.cos(a), 0.95 * math.sin(a), 0.12)
end
cmd.snow.level(3.5)
print(string.format("ring.lua: %d flakes", count + 1))
