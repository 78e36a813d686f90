-- A norm's revision is the norm-set version at which it last changed: unique over the store's
-- whole history, so an ETag taken before a delete, an import or a re-created id never matches
-- again.
ALTER TABLE norms ADD COLUMN revision INTEGER NOT NULL DEFAULT 0;
UPDATE norms SET revision = (SELECT version FROM norm_set WHERE id = 1);

-- Every change to norms and verbs, written in the change's own transaction: when, by which
-- token label, what it was before and after (canonical JSON, null where there was none).
CREATE TABLE audit (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    at          TEXT    NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
    actor       TEXT    NOT NULL,
    subject     TEXT    NOT NULL CHECK (subject IN ('norm', 'action', 'norm_set')),
    operation   TEXT    NOT NULL CHECK (operation IN ('create', 'replace', 'delete', 'import')),
    target      TEXT,
    before_json TEXT,
    after_json  TEXT,
    version     INTEGER NOT NULL -- the version of the changed set after the change
);
