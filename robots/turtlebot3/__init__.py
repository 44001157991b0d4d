"""baobab subpackage."""
