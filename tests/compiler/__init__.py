"""The compiler's layers: the model, the derivation, the emission plan, verification and generation."""
