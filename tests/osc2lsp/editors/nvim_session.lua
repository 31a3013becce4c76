-- A scripted headless Neovim (0.7 or newer) session against osc2lsp.
--
--   nvim --headless -n -i NONE -u nvim_session.lua   with OSC2LSP_SPEC=<spec.json>
--
-- The spec names the server command, the file to open, the edits to make (with
-- nvim_buf_set_text, so that Neovim's own LSP client sends them as incremental
-- changes) and where to write what the session saw: the diagnostics once they
-- equal the expected ones (or at the deadline), and the buffer after
-- formatting with Neovim's default options (noexpandtab, shiftwidth 8).

local function read_json(path)
  local file = assert(io.open(path, "r"))
  local data = file:read("*a")
  file:close()
  return vim.fn.json_decode(data)
end

local spec = read_json(os.getenv("OSC2LSP_SPEC"))
local result = { events = {} }

local function finish()
  local out = assert(io.open(spec.result, "w"))
  out:write(vim.fn.json_encode(result))
  out:close()
  vim.cmd("qall!")
end

local function seen()
  local found = {}
  for _, d in ipairs(vim.diagnostic.get(0)) do
    local code = d.code or (d.user_data and d.user_data.lsp and d.user_data.lsp.code)
    table.insert(found, { d.lnum, d.col, code, d.message })
  end
  table.sort(found, function(a, b)
    if a[1] ~= b[1] then return a[1] < b[1] end
    if a[2] ~= b[2] then return a[2] < b[2] end
    return tostring(a[3]) < tostring(b[3])
  end)
  return found
end

local function same(a, b)
  return vim.fn.json_encode(a) == vim.fn.json_encode(b)
end

local ok, err = pcall(function()
  vim.cmd("edit " .. vim.fn.fnameescape(spec.file))
  local buf = vim.api.nvim_get_current_buf()
  local client_id = vim.lsp.start_client({
    name = "osc2lsp",
    cmd = spec.cmd,
    cmd_env = spec.env,
    root_dir = spec.root,
    init_options = spec.init_options,
  })
  assert(client_id, "the server did not start")
  vim.lsp.buf_attach_client(buf, client_id)
  assert(vim.wait(spec.timeout_ms, function()
    local client = vim.lsp.get_client_by_id(client_id)
    return client ~= nil and client.initialized
  end, 20), "initialize was not answered")
  result.initialized = true
  -- Diagnostics of the file as opened.
  vim.wait(spec.timeout_ms, function() return same(seen(), spec.expected_before) end, 20)
  result.before = seen()
  -- The edits, one at a time, as a user makes them.
  for _, e in ipairs(spec.edits) do
    vim.api.nvim_buf_set_text(buf, e[1], e[2], e[3], e[4], e[5])
  end
  result.text = table.concat(vim.api.nvim_buf_get_lines(buf, 0, -1, false), "\n")
  vim.wait(spec.timeout_ms, function() return same(seen(), spec.expected_after) end, 20)
  result.after = seen()
  -- Formatting with Neovim's defaults: it asks for tabs of width 8.
  result.format_options = vim.lsp.util.make_formatting_params().options
  vim.lsp.buf.formatting_sync(nil, spec.timeout_ms)
  result.formatted = table.concat(vim.api.nvim_buf_get_lines(buf, 0, -1, false), "\n")
  vim.lsp.stop_client(client_id)
  vim.wait(spec.timeout_ms, function() return vim.lsp.get_client_by_id(client_id) == nil end, 20)
  result.stopped = vim.lsp.get_client_by_id(client_id) == nil
end)
if not ok then
  result.error = tostring(err)
end
finish()
