-- `put` takes two different objects: a cup is not put on itself. The seeded definition gains
-- `distinct`; a `put` a curator has rewritten is left as written. The library version is
-- not moved: a process started before this ran is an older build, which cannot read `distinct`
-- and fails closed (503) until it is upgraded too.
UPDATE actions SET definition = '{"name":"put","parameters":["X","Y"],"joiner":"on","distinct":true,"methods":[{"steps":["get(X)","itself"],"reach":["X","Y"],"place":["X","Y"],"adds":["on(X,Y)"],"removes":["holding(self,X)"]}]}'
    WHERE name = 'put'
      AND definition = '{"name":"put","parameters":["X","Y"],"joiner":"on","methods":[{"steps":["get(X)","itself"],"reach":["X","Y"],"place":["X","Y"],"adds":["on(X,Y)"],"removes":["holding(self,X)"]}]}';
