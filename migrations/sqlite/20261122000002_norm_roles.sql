-- Roles: a norm may apply only to speakers with certain roles, or exempt some.
ALTER TABLE norms ADD COLUMN roles_json TEXT NOT NULL DEFAULT '[]';
ALTER TABLE norms ADD COLUMN exempt_roles_json TEXT NOT NULL DEFAULT '[]';
