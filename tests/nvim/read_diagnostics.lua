-- Headless Neovim 0.7+: attach `ncverify lsp` to each file named in NCVERIFY_FILES
-- (separated by newlines), wait for its diagnostics, and write them as JSON to NCVERIFY_OUT.
local command = vim.fn.json_decode(os.getenv("NCVERIFY_SERVER"))
local client = vim.lsp.start_client({ name = "ncverify", cmd = command, root_dir = vim.fn.getcwd() })
local found = {}
for _, path in ipairs(vim.split(os.getenv("NCVERIFY_FILES"), "\n", { trimempty = true })) do
  vim.cmd("edit " .. vim.fn.fnameescape(path))
  local buffer = vim.api.nvim_get_current_buf()
  vim.lsp.buf_attach_client(buffer, client)
  vim.wait(90000, function() return #vim.diagnostic.get(buffer) > 0 end, 50)
  local items = {}
  for _, item in ipairs(vim.diagnostic.get(buffer)) do
    local lsp = item.user_data and item.user_data.lsp or {}
    table.insert(items, { line = item.lnum + 1, code = item.code or lsp.code, severity = item.severity, message = item.message })
  end
  found[path] = items
end
local out = io.open(os.getenv("NCVERIFY_OUT"), "w")
out:write(vim.fn.json_encode(found))
out:close()
vim.lsp.stop_client(client)
vim.cmd("qall!")
