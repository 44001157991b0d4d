"""The mission language: loading a mission file, its models, parameters and poses, the tree
parser and compiler, the JSON Schema and the tree exports."""
