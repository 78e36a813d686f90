-- Verbs carry the words that name them when a directive comes in words, and put the words
-- understood between its arguments. The defaults are added only to verbs that have no words
-- (or, for put, no joiners) yet, so a verb a curator has given words keeps them; joiners only
-- when put still has two parameters. The library version is not moved: a process started
-- before this ran is an older build, which cannot read `words` and fails closed (503) once it
-- rereads the library, until it is upgraded too.
UPDATE actions SET definition = jsonb_set(definition::jsonb, '{words}', '["get","grab","take","pick up","fetch","bring","hand"]'::jsonb)::text
WHERE name = 'get' AND NOT (definition::jsonb ? 'words');
UPDATE actions SET definition = jsonb_set(definition::jsonb, '{words}', '["put","place","set","position"]'::jsonb)::text
WHERE name = 'put' AND NOT (definition::jsonb ? 'words');
UPDATE actions SET definition = jsonb_set(definition::jsonb, '{words}', '["destroy","break","smash","wreck"]'::jsonb)::text
WHERE name = 'destroy' AND NOT (definition::jsonb ? 'words');
UPDATE actions SET definition = jsonb_set(definition::jsonb, '{words}', '["steal"]'::jsonb)::text
WHERE name = 'steal' AND NOT (definition::jsonb ? 'words');
UPDATE actions SET definition = jsonb_set(definition::jsonb, '{words}', '["point to","point at"]'::jsonb)::text
WHERE name = 'pointTo' AND NOT (definition::jsonb ? 'words');
UPDATE actions SET definition = jsonb_set(definition::jsonb, '{joiners}', '["on","onto","in","into","upon","inside"]'::jsonb)::text
WHERE name = 'put' AND NOT (definition::jsonb ? 'joiners')
  AND jsonb_array_length(definition::jsonb -> 'parameters') = 2;
