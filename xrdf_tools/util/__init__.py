"""Cross-cutting helpers with no domain knowledge: errors, file input/output, the safe XML parser,
graphs, rotations, frozen maps."""
