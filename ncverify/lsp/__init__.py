"""``ncverify lsp``: the language server (needs the ``lsp`` extra: pygls 2 and lsprotocol)."""
from .server import serve

__all__ = ["serve"]
