-- Norm ids a client may send are 1..=2^53-1, exact in every JSON client. An import made before
-- that bound was checked could store an id beyond it, and AUTOINCREMENT then had no id left to
-- give: every later create failed, even after that norm was deleted. Such norms are renumbered
-- after the largest id in range (their content and revision stay), and the id sequence is
-- brought back within range, so creating works again.
CREATE TEMP TABLE renumbered AS
    SELECT id AS old,
           (SELECT COALESCE(MAX(id), 0) FROM norms WHERE id <= 9007199254740991)
               + ROW_NUMBER() OVER (ORDER BY id) AS new
    FROM norms
    WHERE id > 9007199254740991;
UPDATE norms SET id = (SELECT new FROM renumbered WHERE old = norms.id)
    WHERE id IN (SELECT old FROM renumbered);
DROP TABLE renumbered;
UPDATE sqlite_sequence SET seq = (SELECT COALESCE(MAX(id), 0) FROM norms)
    WHERE name = 'norms' AND seq > 9007199254740991;
