-- The action library as data, one verb per row, seeded with the contract's default library.
-- `definition` is the verb as a curator writes it (JSON: parameters, joiner, methods).
CREATE TABLE actions (
    name       TEXT PRIMARY KEY,
    definition TEXT NOT NULL,
    updated_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);

-- Bumped with every change to `actions`, like norm_set for norms.
CREATE TABLE action_set (
    id      INTEGER PRIMARY KEY CHECK (id = 1),
    version INTEGER NOT NULL
);
INSERT INTO action_set (id, version) VALUES (1, 1);

INSERT INTO actions (name, definition) VALUES
    ('destroy', '{"name":"destroy","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"adds":["destroyed(X)"]}]}'),
    ('get', '{"name":"get","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"grasp":["X"],"adds":["holding(self,X)"]}]}'),
    ('pointTo', '{"name":"pointTo","parameters":["X"],"methods":[{"steps":["itself"]}]}'),
    ('put', '{"name":"put","parameters":["X","Y"],"joiner":"on","methods":[{"steps":["get(X)","itself"],"reach":["X","Y"],"place":["X","Y"],"adds":["on(X,Y)"],"removes":["holding(self,X)"]}]}'),
    ('steal', '{"name":"steal","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"grasp":["X"],"adds":["holding(self,X)"]}]}');
