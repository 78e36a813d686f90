-- Soft norms: kinds discouraged_action, discouraged_state (should not) and preferred_action,
-- preferred_state (should) join the forbidden kinds. SQLite cannot alter a CHECK constraint, so
-- the table is rebuilt with every column and row as it was; the id sequence is carried over, so
-- ids of deleted norms are still never reused.
CREATE TABLE norms_soft (
    id                INTEGER PRIMARY KEY AUTOINCREMENT,
    kind              TEXT    NOT NULL CHECK (kind IN ('forbidden_action', 'forbidden_state',
                                                       'discouraged_action', 'discouraged_state',
                                                       'preferred_action', 'preferred_state')),
    term              TEXT    NOT NULL,             -- canonical action or state
    when_json         TEXT    NOT NULL DEFAULT '[]', -- JSON array of canonical terms
    context           TEXT,
    severity          INTEGER NOT NULL DEFAULT 3 CHECK (severity BETWEEN 1 AND 5),
    note              TEXT,
    created_at        TEXT    NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
    roles_json        TEXT    NOT NULL DEFAULT '[]',
    exempt_roles_json TEXT    NOT NULL DEFAULT '[]',
    revision          INTEGER NOT NULL DEFAULT 0
);
INSERT INTO norms_soft (id, kind, term, when_json, context, severity, note, created_at, roles_json,
                        exempt_roles_json, revision)
    SELECT id, kind, term, when_json, context, severity, note, created_at, roles_json,
           exempt_roles_json, revision
    FROM norms;
CREATE TEMP TABLE norms_sequence AS SELECT seq FROM sqlite_sequence WHERE name = 'norms';
DROP TABLE norms;
ALTER TABLE norms_soft RENAME TO norms;
-- The copy set the new table's sequence to its largest id; the old one may have been past it.
UPDATE sqlite_sequence SET seq = MAX(seq, COALESCE((SELECT seq FROM norms_sequence), 0))
    WHERE name = 'norms';
INSERT INTO sqlite_sequence (name, seq)
    SELECT 'norms', seq FROM norms_sequence
    WHERE NOT EXISTS (SELECT 1 FROM sqlite_sequence WHERE name = 'norms');
DROP TABLE norms_sequence;
