"""Small benchmark models with closed-form or independently computable answers."""
