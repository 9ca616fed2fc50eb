"""What HEIDENHAIN Klartext operations and cycles do when the interpreter reaches them."""
