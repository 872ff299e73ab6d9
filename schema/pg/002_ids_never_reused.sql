-- Locus schema v2, PostgreSQL: nothing to do. SQLite needed AUTOINCREMENT for ids never to be
-- handed out twice; v1's identity sequences already never go back.
SELECT 1;
