using System.Globalization;
using Microsoft.Data.Sqlite;

namespace PmacStream.Preparation.Store;

/// <summary>The preparations stored with a revision, on SQLite.</summary>
public sealed partial class ProgramStore
{
    private const string PreparationColumns = "id, program_id, inputs_key, inputs, manifest";

    /// <inheritdoc />
    public StoredPreparation? FindPreparation(long programId, string inputsKey)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {PreparationColumns} FROM preparations WHERE program_id = $p AND inputs_key = $k";
        cmd.Parameters.AddWithValue("$p", programId);
        cmd.Parameters.AddWithValue("$k", inputsKey);
        using var r = cmd.ExecuteReader();
        return r.Read() ? PreparationFiles.ReadRow(r) : null;
    }

    /// <inheritdoc />
    public IReadOnlyList<StoredPreparation> ListPreparations(long programId)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = $"SELECT {PreparationColumns} FROM preparations WHERE program_id = $p ORDER BY id";
        cmd.Parameters.AddWithValue("$p", programId);
        using var r = cmd.ExecuteReader();
        var list = new List<StoredPreparation>();
        while (r.Read())
        {
            list.Add(PreparationFiles.ReadRow(r));
        }

        return list;
    }

    /// <inheritdoc />
    public IEnumerable<(string Name, byte[] Data)> ReadPreparationFiles(long preparationId)
    {
        using var cmd = _connection.CreateCommand();
        cmd.CommandText = string.Format(CultureInfo.InvariantCulture, PreparationFiles.SelectFiles, "$p");
        cmd.Parameters.AddWithValue("$p", preparationId);
        using var r = cmd.ExecuteReader();
        while (r.Read())
        {
            yield return (r.GetString(0), (byte[])r.GetValue(1));
        }
    }

    /// <inheritdoc />
    public StoredPreparation StorePreparation(long programId, string inputs, string folder)
    {
        ArgumentNullException.ThrowIfNull(inputs);
        var key = StoredPreparation.KeyOf(inputs);
        var manifestText = File.ReadAllText(System.IO.Path.Combine(folder, ChunkManifest.FileName));
        var manifest = ChunkManifest.Load(System.IO.Path.Combine(folder, ChunkManifest.FileName));
        using var tx = _connection.BeginTransaction();
        long id;
        using (var cmd = _connection.CreateCommand())
        {
            cmd.Transaction = tx;
            cmd.CommandText = "INSERT INTO preparations (program_id, inputs_key, inputs, manifest, created) VALUES ($p, $k, $i, $m, $c) " +
                              "ON CONFLICT (program_id, inputs_key) DO NOTHING RETURNING id";
            cmd.Parameters.AddWithValue("$p", programId);
            cmd.Parameters.AddWithValue("$k", key);
            cmd.Parameters.AddWithValue("$i", inputs);
            cmd.Parameters.AddWithValue("$m", manifestText);
            cmd.Parameters.AddWithValue("$c", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            if (cmd.ExecuteScalar() is not long inserted)
            {
                tx.Rollback();
                return FindPreparation(programId, key)!;
            }

            id = inserted;
        }

        using (var file = _connection.CreateCommand())
        {
            file.Transaction = tx;
            file.CommandText = "INSERT INTO preparation_files (preparation_id, seq, name, data) VALUES ($id, $s, $n, $d)";
            var (pid, seq, name, data) = (file.Parameters.Add("$id", SqliteType.Integer), file.Parameters.Add("$s", SqliteType.Integer),
                file.Parameters.Add("$n", SqliteType.Text), file.Parameters.Add("$d", SqliteType.Blob));
            pid.Value = id;
            var n = 0;
            foreach (var (fileName, bytes) in PreparationFiles.Read(folder, manifest))
            {
                (seq.Value, name.Value, data.Value) = (n++, fileName, bytes);
                file.ExecuteNonQuery();
            }
        }

        tx.Commit();
        return new StoredPreparation(id, programId, key, inputs, manifestText);
    }
}
