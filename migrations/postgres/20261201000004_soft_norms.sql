-- Soft norms: kinds discouraged_action, discouraged_state (should not) and preferred_action,
-- preferred_state (should) join the forbidden kinds. The check on `kind` is replaced, whatever
-- name the server gave it.
DO $$
DECLARE
    old record;
BEGIN
    FOR old IN
        SELECT conname FROM pg_constraint
        WHERE conrelid = 'norms'::regclass AND contype = 'c'
          AND pg_get_constraintdef(oid) LIKE '%kind%'
    LOOP
        EXECUTE format('ALTER TABLE norms DROP CONSTRAINT %I', old.conname);
    END LOOP;
END
$$;
ALTER TABLE norms ADD CONSTRAINT norms_kind_check CHECK (kind IN (
    'forbidden_action', 'forbidden_state',
    'discouraged_action', 'discouraged_state',
    'preferred_action', 'preferred_state'));
