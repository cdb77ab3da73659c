namespace PmacStream.IntegrationTests.Streaming;

public class ResumeMissingDbTests
{
    [Fact]
    public void Resume_with_a_missing_job_database_says_so_and_creates_nothing()
    {
        using var temp = new TestFolder("resume");
        var dir = Path.Combine(temp.Path, "missing");
        var db = Path.Combine(dir, "sub", "jobs.db");

        var (code, _, stderr) = CliRun.InProcess("resume", "--job-db", db, "--yes");

        code.Should().Be(2);
        stderr.Should().Contain(db).And.Contain("no job database");
        Directory.Exists(dir).Should().BeFalse("resume only reads jobs");
    }
}
