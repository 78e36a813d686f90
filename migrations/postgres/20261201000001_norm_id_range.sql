-- Norm ids a client may send are 1..=2^53-1, exact in every JSON client. An import made before
-- that bound was checked could store an id beyond it and push the id sequence to its end, so
-- that every later create failed. Such norms are renumbered after the largest id in range
-- (their content and revision stay), and a sequence beyond the range is brought back to just
-- past the largest id, so creating works again.
CREATE TEMP TABLE renumbered ON COMMIT DROP AS
    SELECT id AS old,
           (SELECT COALESCE(MAX(id), 0) FROM norms WHERE id <= 9007199254740991)
               + ROW_NUMBER() OVER (ORDER BY id) AS new
    FROM norms
    WHERE id > 9007199254740991;
UPDATE norms SET id = renumbered.new FROM renumbered WHERE norms.id = renumbered.old;
DO $$
DECLARE
    sequence_name text := pg_get_serial_sequence('norms', 'id');
    last bigint;
BEGIN
    EXECUTE format('SELECT last_value FROM %s', sequence_name) INTO last;
    IF last > 9007199254740991 THEN
        PERFORM setval(sequence_name, (SELECT COALESCE(MAX(id), 0) FROM norms) + 1, false);
    END IF;
END
$$;
