using System.Globalization;
using Npgsql;
using NpgsqlTypes;

namespace PmacStream.Preparation.Store;

/// <summary>The preparations stored with a revision, on PostgreSQL: the chunk text itself is in the database, so any station runs them.</summary>
public sealed partial class PgProgramStore
{
    private const string PreparationColumns = "id, program_id, inputs_key, inputs, manifest";

    /// <inheritdoc />
    public StoredPreparation? FindPreparation(long programId, string inputsKey)
    {
        using var cmd = new NpgsqlCommand($"SELECT {PreparationColumns} FROM preparations WHERE program_id = @p AND inputs_key = @k", _connection);
        cmd.Parameters.AddWithValue("p", programId);
        cmd.Parameters.AddWithValue("k", inputsKey);
        using var r = cmd.ExecuteReader();
        return r.Read() ? PreparationFiles.ReadRow(r) : null;
    }

    /// <inheritdoc />
    public IReadOnlyList<StoredPreparation> ListPreparations(long programId)
    {
        using var cmd = new NpgsqlCommand($"SELECT {PreparationColumns} FROM preparations WHERE program_id = @p ORDER BY id", _connection);
        cmd.Parameters.AddWithValue("p", programId);
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
        using var cmd = new NpgsqlCommand(string.Format(CultureInfo.InvariantCulture, PreparationFiles.SelectFiles, "@p"), _connection);
        cmd.Parameters.AddWithValue("p", preparationId);
        using var r = cmd.ExecuteReader(System.Data.CommandBehavior.SequentialAccess);
        while (r.Read())
        {
            var name = r.GetString(0);
            yield return (name, r.GetFieldValue<byte[]>(1));
        }
    }

    /// <inheritdoc />
    public StoredPreparation StorePreparation(long programId, string inputs, string folder)
    {
        ArgumentNullException.ThrowIfNull(inputs);
        var key = StoredPreparation.KeyOf(inputs);
        var manifestText = File.ReadAllText(Path.Combine(folder, ChunkManifest.FileName));
        var manifest = ChunkManifest.Load(Path.Combine(folder, ChunkManifest.FileName));
        using var tx = _connection.BeginTransaction();
        long id;
        using (var cmd = new NpgsqlCommand(
                   "INSERT INTO preparations (program_id, inputs_key, inputs, manifest, created) VALUES (@p, @k, @i, @m, @c) " +
                   "ON CONFLICT (program_id, inputs_key) DO NOTHING RETURNING id", _connection, tx))
        {
            cmd.Parameters.AddWithValue("p", programId);
            cmd.Parameters.AddWithValue("k", key);
            cmd.Parameters.AddWithValue("i", inputs);
            cmd.Parameters.AddWithValue("m", manifestText);
            cmd.Parameters.AddWithValue("c", DateTimeOffset.UtcNow.ToString("O", CultureInfo.InvariantCulture));
            if (cmd.ExecuteScalar() is not long inserted)
            {
                tx.Rollback();
                return FindPreparation(programId, key)!;
            }

            id = inserted;
        }

        using (var copy = _connection.BeginBinaryImport("COPY preparation_files (preparation_id, seq, name, data) FROM STDIN (FORMAT BINARY)"))
        {
            var n = 0;
            foreach (var (fileName, bytes) in PreparationFiles.Read(folder, manifest))
            {
                copy.StartRow();
                copy.Write(id, NpgsqlDbType.Bigint);
                copy.Write(n++, NpgsqlDbType.Integer);
                copy.Write(fileName, NpgsqlDbType.Text);
                copy.Write(bytes, NpgsqlDbType.Bytea);
            }

            copy.Complete();
        }

        tx.Commit();
        return new StoredPreparation(id, programId, key, inputs, manifestText);
    }
}
