"""Cross-cutting helpers with no domain knowledge: errors, file input/output, graphs, rotations,
frozen maps."""
