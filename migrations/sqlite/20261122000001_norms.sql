-- Norms, one row each; ids are never reused (AUTOINCREMENT), so an id in a log stays unambiguous.
CREATE TABLE norms (
    id         INTEGER PRIMARY KEY AUTOINCREMENT,
    kind       TEXT    NOT NULL CHECK (kind IN ('forbidden_action', 'forbidden_state')),
    term       TEXT    NOT NULL,             -- canonical action or state
    when_json  TEXT    NOT NULL DEFAULT '[]', -- JSON array of canonical terms
    context    TEXT,
    severity   INTEGER NOT NULL DEFAULT 3 CHECK (severity BETWEEN 1 AND 5),
    note       TEXT,
    created_at TEXT    NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);

-- One row: bumped in the same transaction as every norm change, so one cheap read tells any
-- process whether its compiled norm set is stale.
CREATE TABLE norm_set (
    id      INTEGER PRIMARY KEY CHECK (id = 1),
    version INTEGER NOT NULL
);
INSERT INTO norm_set (id, version) VALUES (1, 0);
