"""Compiling printed C: translation units in parallel (`compile`), the CPython extension's glue and the
private cache of compiled modules (`extension`), and the C every vector batch needs (`lanes`)."""
