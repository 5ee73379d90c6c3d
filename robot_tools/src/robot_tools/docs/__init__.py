"""The product's generated documentation (make docs)."""
