"""Reading Modelica source with the grammar of the Modelica Language Specification (docs/modelica.md)."""
