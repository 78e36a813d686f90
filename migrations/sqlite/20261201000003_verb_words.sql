-- Verbs carry the words that name them when a directive comes in words, and put the words
-- understood between its arguments. The defaults are added only to verbs that have no words
-- (or, for put, no joiners) yet, so a verb a curator has given words keeps them; joiners only
-- when put still has two parameters. The library version is not moved: a process started
-- before this ran is an older build, which cannot read `words` and fails closed (503) once it
-- rereads the library, until it is upgraded too.
UPDATE actions SET definition = json_set(definition, '$.words', json('["get","grab","take","pick up","fetch","bring","hand"]'))
    WHERE name = 'get' AND json_valid(definition) AND json_extract(definition, '$.words') IS NULL;
UPDATE actions SET definition = json_set(definition, '$.words', json('["put","place","set","position"]'))
    WHERE name = 'put' AND json_valid(definition) AND json_extract(definition, '$.words') IS NULL;
UPDATE actions SET definition = json_set(definition, '$.words', json('["destroy","break","smash","wreck"]'))
    WHERE name = 'destroy' AND json_valid(definition) AND json_extract(definition, '$.words') IS NULL;
UPDATE actions SET definition = json_set(definition, '$.words', json('["steal"]'))
    WHERE name = 'steal' AND json_valid(definition) AND json_extract(definition, '$.words') IS NULL;
UPDATE actions SET definition = json_set(definition, '$.words', json('["point to","point at"]'))
    WHERE name = 'pointTo' AND json_valid(definition) AND json_extract(definition, '$.words') IS NULL;
UPDATE actions SET definition = json_set(definition, '$.joiners', json('["on","onto","in","into","upon","inside"]'))
    WHERE name = 'put' AND json_valid(definition) AND json_extract(definition, '$.joiners') IS NULL
      AND json_array_length(definition, '$.parameters') = 2;
