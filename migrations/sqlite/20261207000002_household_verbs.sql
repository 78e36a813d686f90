-- The household verbs of the contract of 2026-12-06: give, heat, open, close, discard, clean,
-- pour, cut, switchOn and switchOff, each added only where no verb of that name is stored (a
-- curator's is kept as written). A word names one verb: a new verb is given only the words no
-- stored verb has, so a library in which a curator gave "wash" or "hand" to a verb still loads.
-- "hand" and "bring" move from `get` to `give` only where `get` still has exactly its default
-- words. The library version is not moved: a process started before this ran is an older
-- build, which cannot read `implied` and fails closed (503) once it rereads the library, until
-- it is upgraded too.
UPDATE actions SET definition = json_set(definition, '$.words', json('["get","grab","take","pick up","fetch"]'))
WHERE name = 'get' AND json_valid(definition)
  AND json(json_extract(definition, '$.words')) = json('["get","grab","take","pick up","fetch","bring","hand"]');
WITH household(name, definition, words) AS (VALUES
    ('give',
     '{"name":"give","parameters":["X","P"],"joiner":"to","distinct":true,"methods":[{"steps":["get(X)","itself"],"reach":["P"],"preconditions":["person(P)"],"adds":["holding(P,X)"],"removes":["holding(self,X)"]}],"joiners":["to"]}',
     '["give","hand","pass","bring"]'),
    ('heat',
     '{"name":"heat","parameters":["X","Y"],"joiner":"with","distinct":true,"implied":{"Y":["heater(Y)"]},"methods":[{"steps":["get(X)","itself"],"reach":["Y"],"preconditions":["heater(Y)"],"adds":["hot(X)"],"removes":["holding(self,X)"]}],"joiners":["in","on","with"]}',
     '["heat","heat up","warm","warm up"]'),
    ('open',
     '{"name":"open","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"preconditions":["closed(X)"],"adds":["open(X)"],"removes":["closed(X)"]}]}',
     '["open"]'),
    ('close',
     '{"name":"close","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"preconditions":["open(X)"],"adds":["closed(X)"],"removes":["open(X)"]}]}',
     '["close","shut"]'),
    ('discard',
     '{"name":"discard","parameters":["X"],"methods":[{"steps":["get(X)","itself"],"adds":["discarded(X)"],"removes":["holding(self,X)"]}]}',
     '["throw away","throw out","discard","dispose of","get rid of"]'),
    ('clean',
     '{"name":"clean","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"adds":["clean(X)"],"removes":["dirty(X)"]}]}',
     '["wash","clean","rinse","wipe"]'),
    ('pour',
     '{"name":"pour","parameters":["X","Y"],"joiner":"into","distinct":true,"methods":[{"steps":["get(X)","itself"],"reach":["Y"],"adds":["in(X,Y)"]}],"joiners":["into","in"]}',
     '["pour"]'),
    ('cut',
     '{"name":"cut","parameters":["X","Y"],"joiner":"with","distinct":true,"implied":{"Y":["knife(Y)"]},"methods":[{"steps":["get(Y)","itself"],"reach":["X"],"preconditions":["knife(Y)"],"adds":["cut(X)"]}],"joiners":["with"]}',
     '["cut","chop","slice","dice"]'),
    ('switchOn',
     '{"name":"switchOn","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"adds":["powered(X)"]}]}',
     '["turn on","switch on"]'),
    ('switchOff',
     '{"name":"switchOff","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"removes":["powered(X)"]}]}',
     '["turn off","switch off"]'))
INSERT INTO actions (name, definition)
SELECT h.name, json_set(json(h.definition), '$.words', json((
    SELECT json_group_array(w.value) FROM json_each(h.words) AS w
    WHERE NOT EXISTS (
        SELECT 1 FROM actions AS a,
             json_each(CASE WHEN json_valid(a.definition) THEN a.definition ELSE '{}' END, '$.words') AS x
        WHERE x.value = w.value))))
FROM household AS h
WHERE NOT EXISTS (SELECT 1 FROM actions WHERE name = h.name);
