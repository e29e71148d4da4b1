"""Data package: the Orthoglide xacro description, its loop data and rendered URDFs."""
