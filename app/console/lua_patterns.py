"""Lua's pattern functions for the Lua sandbox (app/console/lua.py), bounded like script code.

``string.find``, ``match``, ``gmatch`` and ``gsub`` run in C, where the count hook never fires, and
the C matcher backtracks: ``("a"):rep(40):find(".-.-.-.-.-.-.-.-.-.-.-b")`` would run for hours.
So each call first bounds the C matcher's work from the subject's length and the pattern's items
(``match_cost`` below: a ``* + -`` item may try the rest of the pattern after each of the n bytes
it can take, a ``?`` item twice, ``%b`` and back-references scan up to n bytes, an unanchored
pattern is tried at every start; a plain search costs the bytes searched times the text's length).
A call whose bound is at most `WORK_LIMIT` steps (about a millisecond of C) runs in C; any other
runs in a Lua port of Lua 5.4's matcher, where the count hook and the clock stop it like any
script code. The port returns what the C functions return and raises their errors
(tests/test_lua.py compares them on many patterns).
"""

WORK_LIMIT = 200_000  # steps of the C matcher one call may take (a step: one byte against one item)

# Runs once per LuaRuntime with the full standard library, before the sandbox replaces the string
# library's pattern functions with the bounded ones it returns. (With WORK_LIMIT 0 every call runs
# in the port: tests compare it with the C functions that way.)
PATTERNS = r"""
local WORK_LIMIT = ...
local C = {find = string.find, match = string.match, gmatch = string.gmatch, gsub = string.gsub}
local byte, sub, char, concat, unpack = string.byte, string.sub, string.char, table.concat, table.unpack
local error, type, tostring, tointeger, min, setmetatable =
      error, type, tostring, math.tointeger, math.min, setmetatable

local MAXCCALLS, MAXCAPTURES = 200, 32  -- lstrlib.c's limits: the matcher's recursion, captures
local CAP_UNFINISHED, CAP_POSITION = -1, -2
local ESC, LBRACKET, RBRACKET, CARET, DOT, DOLLAR, LPAREN, RPAREN, STAR, PLUS, DASH, QUESTION =
      byte("%[]^.$()*+-?", 1, -1)
local LETTER_B, LETTER_F, ZERO, ONE, NINE = byte("bf019", 1, -1)
local SPECIALS = "[%^%$%*%+%?%.%(%[%%%-]"  -- a pattern without these is searched for as plain text
local HUGE = math.huge
local DONE = HUGE  -- as the next item: the subject position is the match's result
local SLICE = 256  -- texts are compared this many bytes per step, so each step is short

-- A single-byte class as the set of bytes it matches: members[byte] is true or nil (as is
-- members[nil], past the subject's end). %a %d ... as the C functions see them (ctype, in this
-- process's locale): ask them.
local CLASSES = {}
for class in C.gmatch("acdglpsuwxzACDGLPSUWXZ", ".") do
  local members = {}
  for c = 0, 255 do members[c] = C.find(char(c), "%" .. class) and true end
  CLASSES[byte(class)] = members
end
local ANY = {}
for c = 0, 255 do ANY[c] = true end
local LITERAL = setmetatable({}, {__index = function(t, c) t[c] = {[c] = true} return t[c] end})

local function fail(message) error(message, 2) end

local function escaped_members(class)  -- %x: a class letter, or any other byte standing for itself
  return CLASSES[class] or LITERAL[class]
end

local function set_match(pat, c, p, ec)  -- [set] from p (its '[') to ec (its ']')
  local found = true
  if byte(pat, p + 1) == CARET then found, p = false, p + 1 end
  p = p + 1
  while p < ec do
    local pc = byte(pat, p)
    if pc == ESC then
      p = p + 1
      if escaped_members(byte(pat, p))[c] then return found end
    elseif byte(pat, p + 1) == DASH and p + 2 < ec then
      if pc <= c and c <= byte(pat, p + 2) then return found end
      p = p + 2
    elseif pc == c then
      return found
    end
    p = p + 1
  end
  return not found
end

local function class_members(pat, p, ep)  -- the class from p to ep (exclusive)
  local c = byte(pat, p)
  if c == DOT then return ANY
  elseif c == ESC then return escaped_members(byte(pat, p + 1))
  elseif c ~= LBRACKET then return LITERAL[c]
  end
  local members = {}
  for b = 0, 255 do members[b] = set_match(pat, b, p, ep - 1) or nil end
  return members
end

-- Where the single-byte class at p ends, or nil and the error the matcher raises on reaching it.
local function class_end(pat, p, plen)
  local c = byte(pat, p)
  p = p + 1
  if c == ESC then
    if p > plen then return nil, "malformed pattern (ends with '%')" end
    return p + 1
  elseif c == LBRACKET then
    if byte(pat, p) == CARET then p = p + 1 end
    repeat  -- the set's first byte is never its end: "[]]" is a set of one ']'
      if p > plen then return nil, "malformed pattern (missing ']')" end
      local pc = byte(pat, p)
      p = p + 1
      if pc == ESC and p <= plen then p = p + 1 end
    until byte(pat, p) == RBRACKET
    return p + 1
  end
  return p
end

-- The pattern item at i: its kind and where the next item starts; a single-byte class also gives
-- its end and suffix (* + - ? or nil). Never raises: a malformed item is kind "error", with the
-- message the matcher raises when it gets there (the C one does not look further ahead).
local function item_at(pat, i, plen)
  local c, nx = byte(pat, i, i + 1)
  if c == LPAREN then
    if nx == RPAREN then return "position", i + 2 end
    return "open", i + 1
  elseif c == RPAREN then
    return "close", i + 1
  elseif c == DOLLAR and i == plen then
    return "end", i + 1
  elseif c == ESC and nx == LETTER_B then
    if i + 2 >= plen then return "error", DONE, "malformed pattern (missing arguments to '%b')" end
    return "balance", i + 4
  elseif c == ESC and nx == LETTER_F then
    if byte(pat, i + 2) ~= LBRACKET then return "error", DONE, "missing '[' after '%f' in pattern" end
    local ep, message = class_end(pat, i + 2, plen)
    if not ep then return "error", DONE, message end
    return "frontier", ep
  elseif c == ESC and nx and ZERO <= nx and nx <= NINE then
    return "backref", i + 2
  end
  local ep, message = class_end(pat, i, plen)
  if not ep then return "error", DONE, message end
  local suffix = byte(pat, ep)
  if suffix == STAR or suffix == PLUS or suffix == DASH or suffix == QUESTION then return "single", ep + 1, ep, suffix end
  return "single", ep, ep
end

-- The port: lstrlib.c's matcher over the pattern's items, compiled once per call, with 1-based
-- subject positions (ms.len + 1 is the end, where C reads the string's terminating zero byte).

local function compile(pat, first)
  local items, plen, i = {}, #pat, first
  while i <= plen do
    local kind, after, ep, suffix = item_at(pat, i, plen)
    local item = {kind = kind}
    if kind == "single" then
      item.members, item.suffix = class_members(pat, i, ep), suffix
    elseif kind == "frontier" then
      item.members = class_members(pat, i + 2, after)
    elseif kind == "balance" then
      item.open, item.close = byte(pat, i + 2, i + 3)
    elseif kind == "backref" then
      item.digit = byte(pat, i + 1)
    elseif kind == "error" then
      item.message = ep
    end
    items[#items + 1] = item
    i = after
  end
  return items
end

local function new_state(src, pat, first)
  local items = compile(pat, first)
  return {src = src, len = #src, items = items, count = #items, level = 0, depth = MAXCCALLS, start = {}, size = {}}
end

local do_match

local function max_expand(ms, s, members, k)  -- greedy: the most repetitions first
  local src, i = ms.src, s
  while members[byte(src, i)] do i = i + 1 end
  for e = i, s, -1 do
    local result = do_match(ms, e, k)
    if result then return result end
  end
  return nil
end

local function min_expand(ms, s, members, k)  -- lazy: the fewest repetitions first
  while true do
    local result = do_match(ms, s, k)
    if result then return result end
    if not members[byte(ms.src, s)] then return nil end
    s = s + 1
  end
end

local function start_capture(ms, s, k, what)
  local level = ms.level
  if level >= MAXCAPTURES then fail("too many captures") end
  ms.start[level], ms.size[level], ms.level = s, what, level + 1
  local e = do_match(ms, s, k)
  if not e then ms.level = level end
  return e
end

local function end_capture(ms, s, k)
  local l = ms.level - 1
  while l >= 0 and ms.size[l] ~= CAP_UNFINISHED do l = l - 1 end
  if l < 0 then fail("invalid pattern capture") end
  ms.size[l] = s - ms.start[l]
  local e = do_match(ms, s, k)
  if not e then ms.size[l] = CAP_UNFINISHED end
  return e
end

local function match_balance(ms, s, open, close)  -- %bxy
  if byte(ms.src, s) ~= open then return nil end
  local depth = 1
  for i = s + 1, ms.len do
    local c = byte(ms.src, i)
    if c == close then
      depth = depth - 1
      if depth == 0 then return i + 1 end
    elseif c == open then
      depth = depth + 1
    end
  end
  return nil
end

local function same_text(a, i, b, j, len)  -- a[i .. i + len - 1] == b[j .. j + len - 1]
  for k = 0, len - 1, SLICE do
    local last = min(k + SLICE, len) - 1
    if sub(a, i + k, i + last) ~= sub(b, j + k, j + last) then return false end
  end
  return true
end

local function match_capture(ms, s, digit)  -- %1 to %9 (and %0, an error)
  local l = digit - ONE
  if l < 0 or l >= ms.level or ms.size[l] == CAP_UNFINISHED then fail("invalid capture index %" .. (l + 1)) end
  local len = ms.size[l]
  if len == CAP_POSITION or ms.len + 1 - s < len or not same_text(ms.src, ms.start[l], ms.src, s, len) then
    return nil
  end
  return s + len
end

local function match_single(ms, s, k, item)  -- a single-byte class and its optional suffix
  local members, suffix = item.members, item.suffix
  if not members[byte(ms.src, s)] then
    if suffix == STAR or suffix == QUESTION or suffix == DASH then return s, k + 1 end
    return nil, DONE
  elseif not suffix then
    return s + 1, k + 1
  elseif suffix == QUESTION then
    local e = do_match(ms, s + 1, k + 1)
    if e then return e, DONE end
    return s, k + 1
  elseif suffix == DASH then
    return min_expand(ms, s, members, k + 1), DONE
  end
  return max_expand(ms, suffix == PLUS and s + 1 or s, members, k + 1), DONE
end

-- Matches item k at subject position s: where matching goes on (s, k), or (result, DONE).
local function match_item(ms, s, k)
  local item = ms.items[k]
  local kind = item.kind
  if kind == "single" then
    return match_single(ms, s, k, item)
  elseif kind == "open" then
    return start_capture(ms, s, k + 1, CAP_UNFINISHED), DONE
  elseif kind == "position" then
    return start_capture(ms, s, k + 1, CAP_POSITION), DONE
  elseif kind == "close" then
    return end_capture(ms, s, k + 1), DONE
  elseif kind == "end" then
    return s == ms.len + 1 and s or nil, DONE
  elseif kind == "balance" then
    s = match_balance(ms, s, item.open, item.close)
  elseif kind == "backref" then
    s = match_capture(ms, s, item.digit)
  elseif kind == "frontier" then
    local previous = s == 1 and 0 or byte(ms.src, s - 1)
    if item.members[previous] or not item.members[byte(ms.src, s) or 0] then s = nil end
  else
    fail(item.message)
  end
  return s, s and k + 1 or DONE
end

-- The end of a match of the items from k at subject position s, or nil.
function do_match(ms, s, k)
  if ms.depth == 0 then fail("pattern too complex") end
  ms.depth = ms.depth - 1
  while k <= ms.count do s, k = match_item(ms, s, k) end
  ms.depth = ms.depth + 1
  return s
end

local function get_capture(ms, i, s, e)  -- capture i (0-based); the whole match if there are none
  if i >= ms.level then
    if i ~= 0 then fail("invalid capture index %" .. (i + 1)) end
    return sub(ms.src, s, e - 1)
  end
  local size = ms.size[i]
  if size == CAP_UNFINISHED then fail("unfinished capture") end
  if size == CAP_POSITION then return ms.start[i] end
  return sub(ms.src, ms.start[i], ms.start[i] + size - 1)
end

local function captures(ms, s, e)  -- all captures; s nil (find) gives none when there are none
  local n = (ms.level == 0 and s) and 1 or ms.level
  local values = {}
  for i = 1, n do values[i] = get_capture(ms, i - 1, s, e) end
  return unpack(values, 1, n)
end

local function start_index(init, len)  -- init as the C functions read it
  if init > 0 then return init
  elseif init == 0 or init < -len then return 1
  end
  return len + init + 1
end

local function anchored(pat)  -- find, match and gsub read a leading '^' as an anchor (gmatch does not)
  return byte(pat) == CARET
end

local function plain_find(s, p, init)  -- lstrlib's lmemfind
  local len, plen = #s, #p
  if plen == 0 then return init, init - 1 end
  local at = C.find(s, sub(p, 1, 1), init, true)
  while at and at + plen - 1 <= len do
    if same_text(s, at, p, 1, plen) then return at, at + plen - 1 end
    at = C.find(s, sub(p, 1, 1), at + 1, true)
  end
  return nil
end

local function find_aux(find, s, p, init, plain)
  local len = #s
  init = start_index(init, len)
  if init > len + 1 then return nil end
  if find and (plain or not C.find(p, SPECIALS)) then return plain_find(s, p, init) end
  local anchor = anchored(p)
  local ms = new_state(s, p, anchor and 2 or 1)
  for start = init, anchor and init or len + 1 do
    ms.level = 0
    local e = do_match(ms, start, 1)
    if e and find then return start, e - 1, captures(ms, nil, e) end
    if e then return captures(ms, start, e) end
  end
  return nil
end

local function lua_find(s, p, init, plain) return find_aux(true, s, p, init, plain) end
local function lua_match(s, p, init) return find_aux(false, s, p, init) end

local function lua_gmatch(s, p, init)
  local len = #s
  local src, lastmatch = min(start_index(init, len), len + 2), nil
  local ms = new_state(s, p, 1)
  return function()
    while src <= len + 1 do
      ms.level = 0
      local e = do_match(ms, src, 1)
      if e and e ~= lastmatch then
        local start = src
        src, lastmatch = e, e
        return captures(ms, start, e)
      end
      src = src + 1
    end
  end
end

local function expand(ms, s, e, repl)  -- a replacement string's %0-%9 and %%
  local pieces, i = {}, 1
  while true do
    local j = C.find(repl, "%", i, true)
    if not j then break end
    local c = byte(repl, j + 1)
    pieces[#pieces + 1] = sub(repl, i, j - 1)
    if c == ESC then pieces[#pieces + 1] = "%"
    elseif c == ZERO then pieces[#pieces + 1] = sub(ms.src, s, e - 1)
    elseif c and ONE <= c and c <= NINE then pieces[#pieces + 1] = tostring(get_capture(ms, c - ONE, s, e))
    else fail("invalid use of '%' in replacement string")
    end
    i = j + 2
  end
  pieces[#pieces + 1] = sub(repl, i)
  return concat(pieces)
end

local function replacement(ms, s, e, repl)
  local value
  if type(repl) == "string" then return expand(ms, s, e, repl)
  elseif type(repl) == "function" then value = repl(captures(ms, s, e))
  else value = repl[get_capture(ms, 0, s, e)]
  end
  if not value then return sub(ms.src, s, e - 1) end  -- nil or false: keep the match
  if type(value) ~= "string" and type(value) ~= "number" then fail("invalid replacement value (a " .. type(value) .. ")") end
  return tostring(value)
end

-- gsub's result in pieces, joined 256 at a time: not a table of millions of short strings.
local function add(result, piece)
  local pieces = result.pieces
  pieces[#pieces + 1] = piece
  if #pieces == 256 then result[#result + 1], result.pieces = concat(pieces), {} end
end

local function lua_gsub(s, p, repl, max_n)
  local len = #s
  local anchor = anchored(p)
  local ms = new_state(s, p, anchor and 2 or 1)
  local result, copied, src, n, lastmatch = {pieces = {}}, 1, 1, 0, nil
  while n < max_n do
    ms.level = 0
    local e = do_match(ms, src, 1)
    if e and e ~= lastmatch then
      n = n + 1
      add(result, sub(s, copied, src - 1))
      add(result, replacement(ms, src, e, repl))
      src, lastmatch, copied = e, e, e
    elseif src <= len then
      src = src + 1
    else
      break
    end
    if anchor then break end
  end
  if n == 0 then return s, 0 end
  add(result, sub(s, copied))
  result[#result + 1] = concat(result.pieces)
  return concat(result), n
end

-- What the C matcher may do, in steps, for pattern p tried at `starts` subject positions with at
-- most n bytes after each: item k takes a_k steps itself and may try the rest of the pattern m_k
-- times, so the pattern costs starts * (a_1 + m_1 * (a_2 + m_2 * (... + 1))). A * + - item scans
-- up to n bytes and tries the rest after each, ? tries it twice, %b and %1 scan up to n bytes, a
-- class costs its length. HUGE for a malformed pattern: the port raises its error.
local function match_cost(p, first, n, starts)
  local plen = #p
  local cost, tries, i = 0, starts, first
  while i <= plen do
    local kind, after, ep, suffix = item_at(p, i, plen)
    local steps, retries = 1, 1
    if kind == "error" then
      return HUGE
    elseif kind == "balance" or kind == "backref" then
      steps = n + 1
    elseif kind == "frontier" then
      steps = 2 * (after - i)
    elseif kind == "single" then
      steps = ep - i
      if suffix == STAR or suffix == PLUS or suffix == DASH then
        steps, retries = (n + 1) * steps, n + 1
      elseif suffix == QUESTION then
        retries = 2
      end
    end
    cost, tries = cost + tries * steps, tries * retries
    if cost + tries > WORK_LIMIT then return HUGE end
    i = after
  end
  return cost + tries
end

local function pattern_cost(p, n)  -- for find, match and gsub
  if anchored(p) then return match_cost(p, 2, n, 1) end
  return match_cost(p, 1, n, n + 1)
end

local function text(v)  -- as the C functions read a string argument: a number stands for its text
  if type(v) == "number" then return tostring(v) end
  return v
end

local function integer(v, default)  -- as they read an optional integer; nil where they raise
  if v == nil then return default end
  return tointeger(v)
end

local function bytes_after(s, init)
  return #s - min(start_index(init, #s), #s + 1) + 1
end

-- Each bounded function calls the C one: with the arguments it was given where they are wrong (it
-- raises its own error before matching anything), or if its work is bounded; else the port.

local function find(s, p, init, plain)
  local s1, p1, i = text(s), text(p), integer(init, 1)
  if type(s1) ~= "string" or type(p1) ~= "string" or not i then C.find(s, p, init, plain) end
  local n = bytes_after(s1, i)
  local plain_search = plain or not C.find(p1, SPECIALS)
  if (plain_search and (n + 1) * (#p1 + 1) or pattern_cost(p1, n)) <= WORK_LIMIT then
    return C.find(s1, p1, i, plain)
  end
  return lua_find(s1, p1, i, plain)
end

local function match(s, p, init)
  local s1, p1, i = text(s), text(p), integer(init, 1)
  if type(s1) ~= "string" or type(p1) ~= "string" or not i then C.match(s, p, init) end
  if pattern_cost(p1, bytes_after(s1, i)) <= WORK_LIMIT then return C.match(s1, p1, i) end
  return lua_match(s1, p1, i)
end

local function gmatch(s, p, init)
  local s1, p1, i = text(s), text(p), integer(init, 1)
  if type(s1) ~= "string" or type(p1) ~= "string" or not i then C.gmatch(s, p, init) end
  local n = bytes_after(s1, i)
  if match_cost(p1, 1, n, n + 1) <= WORK_LIMIT then return C.gmatch(s1, p1, i) end
  return lua_gmatch(s1, p1, i)
end

local function gsub(s, p, repl, max_n)
  local s1, p1, r = text(s), text(p), text(repl)
  local most = type(s1) == "string" and integer(max_n, #s1 + 1)
  local kind = type(r)
  if type(p1) ~= "string" or not most or (kind ~= "string" and kind ~= "function" and kind ~= "table") then
    C.gsub(s, p, repl, max_n)
  end
  if pattern_cost(p1, #s1) <= WORK_LIMIT then return C.gsub(s1, p1, r, most) end
  return lua_gsub(s1, p1, r, most)
end

return {find = find, match = match, gmatch = gmatch, gsub = gsub}
"""  # noqa: E501 (Lua source: its lines keep their numbers in error messages)
