-- Used by docs/neovim_screenshot.py: attach `ncverify lsp`, wait for the diagnostics, and
-- open the float of the finding on the line given in NCVERIFY_LINE.
local client = vim.lsp.start_client({ name = "ncverify", cmd = vim.fn.json_decode(os.getenv("NCVERIFY_SERVER")), root_dir = vim.fn.getcwd() })
vim.lsp.buf_attach_client(0, client)
vim.cmd("syntax on")
vim.wait(90000, function() return #vim.diagnostic.get(0) > 0 end, 50)
vim.api.nvim_win_set_cursor(0, { tonumber(os.getenv("NCVERIFY_LINE")), 8 })
vim.diagnostic.open_float(nil, { scope = "cursor", source = true })
