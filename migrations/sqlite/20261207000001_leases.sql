-- The versions lease of every process serving this store, recorded while it serves. A write is
-- acknowledged only once the longest of them has run out after its commit, so processes
-- started with different `--versions-lease-ms` still see a change on their very next request
-- after it was acknowledged, whichever of them took the write. A process adds its row before
-- it first reads the versions and removes it once it has drained; one killed before that
-- leaves its row, and writes keep waiting its lease (never less than they must) until the row
-- is deleted by hand.
CREATE TABLE leases (
    id       INTEGER PRIMARY KEY AUTOINCREMENT,
    lease_ms INTEGER NOT NULL CHECK (lease_ms >= 0),
    holder   TEXT    NOT NULL, -- the host and process id, for an operator reading this table
    since    TEXT    NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
);
