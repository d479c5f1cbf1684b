!> Tests of mpm_output (HDF5 + XDMF particle output) and mpm_filesystem (state files: test_mpm_output_state).
!>
!> The files written are read back with the plain HDF5 Fortran API (not with mpm_hdf5, the
!> helpers under test), so a mistake in the helpers cannot hide itself. Files go to a fresh
!> folder under $TMPDIR (default /tmp), deleted at the end unless MPM_TEST_KEEP is set.
program test_mpm_output
    use, intrinsic :: iso_c_binding, only: c_char, c_ptr, c_null_char, c_loc
    use hdf5, only: hid_t, hsize_t, size_t, h5fopen_f, h5fclose_f, h5f_acc_rdonly_f, &
        h5dopen_f, h5dclose_f, h5dget_space_f, h5dread_f, h5sget_simple_extent_ndims_f, &
        h5sget_simple_extent_dims_f, h5sclose_f, h5aopen_by_name_f, h5aclose_f, h5aread_f, &
        h5aget_space_f, h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5tclose_f, h5t_fortran_s1, &
        h5t_str_nullpad_f, h5lexists_f, h5kind_to_type, h5_real_kind, h5_integer_kind, &
        h5aexists_f, h5dget_create_plist_f, h5pget_layout_f, h5pclose_f, h5d_virtual_f
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type
    use mpm_strings, only: int_text
    use mpm_case, only: case_type
    use mpm_case_output_fields, only: output_field_index
    use mpm_particles, only: particles_type
    use mpm_grid, only: grid_type, new_grid
    use mpm_output, only: output_writer_type, new_output_writer, write_output, remove_outputs
    use mpm_filesystem, only: make_directory, directory_exists, file_exists, rename_file, &
        remove_file, parent_directory
    use mpm_testing, only: test_suite_type, new_suite, check, check_contains, finish
    use mpm_testing_output, only: tiny_case, fill_particles, open_hdf5_objects, open_test_folder, &
        close_test_folder
    implicit none

    character(len=*), parameter :: files(*) = [character(len=32) :: &
        "out2d/particles_000000.h5", "out2d/particles_000001.h5", "out2d/tiny.xdmf", &
        "out3d/particles_000000.h5", "out3d/cube.xdmf", "out3d_grid/particles_000000.h5", &
        "out3d_grid/cube.xdmf", "parts/notes.txt"]
        !! the files this test leaves, deleted at the end
    character(len=*), parameter :: folders(*) = [character(len=16) :: "a b/c/d", "a b/c", &
        "a b", "out2d", "out3d", "out3d_grid", "parts", ""]
        !! the folders it makes, deepest first

    type(test_suite_type) :: suite
    character(len=:), allocatable :: root
    logical :: keep

    call new_suite(suite, "mpm_output")
    call open_test_folder(suite, "mpm_output_test", root, keep)

    call test_filesystem(suite, root)
    call test_output_2d(suite, root//"/out2d")
    call test_output_3d(suite, root//"/out3d")
    call test_output_parts(suite, root//"/parts")

    call close_test_folder(suite, root, keep, files, folders)
    call finish(suite)

contains

    ! ----------------------------------------------------------------------------------------
    ! Tests
    ! ----------------------------------------------------------------------------------------

    subroutine test_filesystem(suite, root)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: root

        type(error_type), allocatable :: error
        integer :: unit

        call make_directory(root//"/a b/c//d/", error)
        call check(suite, .not. allocated(error), "make_directory with blanks, // and trailing /")
        call check(suite, directory_exists(root//"/a b/c/d"), "nested folder created")
        call make_directory(root//"/a b/c/d", error)
        call check(suite, .not. allocated(error), "make_directory on an existing folder")
        call check(suite, .not. file_exists(root//"/a b"), "a folder is not a file")
        open (newunit=unit, file=root//"/a b/f.txt", status="replace", action="write")
        write (unit, "(a)") "x"
        close (unit)
        call check(suite, file_exists(root//"/a b/f.txt"), "file_exists")
        call make_directory(root//"/a b/f.txt/g", error)
        call check(suite, allocated(error), "make_directory through a file fails")
        if (allocated(error)) call check_contains(suite, error%message, "f.txt' exists and", &
            "make_directory message names the file")
        call rename_file(root//"/a b/f.txt", root//"/a b/c/g.txt", error)
        call check(suite, .not. allocated(error), "rename_file")
        call check(suite, file_exists(root//"/a b/c/g.txt") .and. &
            .not. file_exists(root//"/a b/f.txt"), "file moved")
        call rename_file(root//"/a b/none", root//"/a b/x", error)
        call check(suite, allocated(error), "rename_file of a missing file fails")
        call remove_file(root//"/a b/c/g.txt", error)
        call check(suite, .not. allocated(error) .and. .not. file_exists(root//"/a b/c/g.txt"), &
            "remove_file")
        call check(suite, parent_directory("a/b/c.h5") == "a/b", "parent_directory a/b/c.h5")
        call check(suite, parent_directory("c.h5") == "", "parent_directory c.h5")
        call check(suite, parent_directory("/c.h5") == "/", "parent_directory /c.h5")
        call check(suite, parent_directory("a//c.h5") == "a", "parent_directory a//c.h5")
    end subroutine test_filesystem

    subroutine test_output_2d(suite, dir)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: dir

        type(case_type) :: case
        type(particles_type) :: particles
        type(grid_type) :: grid
        type(output_writer_type) :: writer
        type(error_type), allocatable :: error
        integer(hid_t) :: file
        integer, parameter :: n = 5
        integer :: hdferr, id
        real(wp), allocatable :: values(:, :)
        integer, allocatable :: ints(:)
        character(len=:), allocatable :: xdmf

        call tiny_case(case)
        call fill_particles(suite, case, n, particles)
        call new_grid(grid, case, error)
        call check(suite, .not. allocated(error), "new_grid")
        do id = 1, grid%nnodes
            grid%mass(id) = 0.5_wp*id
            grid%velocity(:, id) = [real(id, wp), -real(id, wp)]
        end do

        call new_output_writer(writer, case, dir, error)
        call check(suite, allocated(error), "new_output_writer refuses a missing folder")
        if (allocated(error)) call check_contains(suite, error%message, dir, &
            "missing folder message names it")
        call make_directory(dir, error)
        call new_output_writer(writer, case, dir//"/", error)
        call check(suite, .not. allocated(error), "new_output_writer")
        call write_output(writer, 10, 0.0_wp, particles, grid, error)
        call check(suite, .not. allocated(error), "first write_output")
        if (allocated(error)) write (*, "(a)") error%message
        ! the index is complete after every write (a run stopped here still opens)
        xdmf = read_text(dir//"/tiny.xdmf")
        call check(suite, count_of(xdmf, 'GridType="Uniform"') == 2 .and. &
            index(xdmf, "particles_000001") == 0 .and. index(xdmf, "</Xdmf>") > 0, &
            "xdmf after the first write lists one time, closed")
        particles%x(1, :) = particles%x(1, :) + 0.1_wp
        call write_output(writer, 20, 0.25_wp, particles, grid, error)
        call check(suite, .not. allocated(error), "second write_output")
        if (allocated(error)) write (*, "(a)") error%message

        call check(suite, file_exists(dir//"/particles_000000.h5"), "particles_000000.h5")
        call check(suite, file_exists(dir//"/particles_000001.h5"), "particles_000001.h5")
        call check(suite, file_exists(dir//"/tiny.xdmf"), "tiny.xdmf")
        call check(suite, .not. file_exists(dir//"/tiny.xdmf.tmp"), "no xdmf .tmp left")
        call check(suite, .not. file_exists(dir//"/particles_000001.h5.tmp"), "no h5 .tmp left")
        call check(suite, open_hdf5_objects() == 0, "write_output leaves no HDF5 object open")

        ! First file: only the time and step differ in what we check here
        call h5fopen_f(dir//"/particles_000000.h5", h5f_acc_rdonly_f, file, hdferr)
        call check(suite, hdferr == 0, "open particles_000000.h5")
        call check(suite, attribute_real(file, ".", "time") == 0.0_wp, "time of output 0")
        call check(suite, attribute_int(file, ".", "step") == 10, "step of output 0")
        call h5fclose_f(file, hdferr)

        call h5fopen_f(dir//"/particles_000001.h5", h5f_acc_rdonly_f, file, hdferr)
        call check(suite, hdferr == 0, "open particles_000001.h5")
        call check(suite, attribute_real(file, ".", "time") == 0.25_wp, "time attribute")
        call check(suite, attribute_int(file, ".", "step") == 20, "step attribute")
        call check(suite, attribute_int(file, ".", "dimension") == 2, "dimension attribute")
        call check(suite, attribute_text(file, ".", "case_name") == "tiny", "case_name")
        call check(suite, len(attribute_text(file, ".", "mpm_geo_version")) > 0, "version")
        call check(suite, attribute_text(file, ".", "material_names", 1) == "sand", &
            "material_names(1)")
        call check(suite, attribute_text(file, ".", "material_names", 2) == "clay", &
            "material_names(2)")

        ! Fortran x(3, n) is HDF5 (n, 3): h5sget_simple_extent_dims_f reports Fortran order
        values = read_reals(file, "particles/position", [3, n])
        call check(suite, all(values(1:2, :) == particles%x), "position x y")
        call check(suite, all(values(3, :) == 0.0_wp), "position z = 0 in 2D")
        call check(suite, attribute_text(file, "particles/position", "units") == "m", &
            "position units")
        values = read_reals(file, "particles/displacement", [3, n])
        call check(suite, all(values(1:2, :) == particles%u) .and. all(values(3, :) == 0.0_wp), &
            "displacement padded")
        values = read_reals(file, "particles/velocity", [3, n])
        call check(suite, all(values(1:2, :) == particles%v) .and. all(values(3, :) == 0.0_wp), &
            "velocity padded")
        call check(suite, attribute_text(file, "particles/velocity", "units") == "m/s", &
            "velocity units")
        values = read_reals(file, "particles/stress", [4, n])
        call check(suite, all(values == particles%stress), "stress values")
        call check(suite, attribute_text(file, "particles/stress", "components") == &
            "xx yy zz xy", "stress components")
        call check(suite, attribute_text(file, "particles/stress", "units") == "Pa", &
            "stress units")
        values = read_reals(file, "particles/strain", [4, n])
        call check(suite, all(values == particles%strain), "strain values")
        call check(suite, attribute_text(file, "particles/strain", "units") == "-", &
            "strain units")
        ints = read_ints(file, "particles/material", n)
        call check(suite, all(ints == particles%material), "material values")
        ! /xdmf: the Polyvertex connectivity and views of the stress and strain columns
        ints = read_ints(file, "xdmf/vertices", n)
        call check(suite, all(ints == [(id, id = 0, n - 1)]), "xdmf/vertices: 0 .. n-1")
        values = read_reals(file, "xdmf/stress_xy", [n])
        call check(suite, all(values(:, 1) == particles%stress(4, :)), &
            "xdmf/stress_xy is column 4 of stress")
        values = read_reals(file, "xdmf/strain_yy", [n])
        call check(suite, all(values(:, 1) == particles%strain(2, :)), &
            "xdmf/strain_yy is column 2 of strain")
        call check(suite, is_virtual(file, "xdmf/stress_xy") .and. &
            is_virtual(file, "xdmf/strain_yy"), "the column views store no copy (virtual)")
        call check(suite, attribute_text(file, "xdmf/stress_xx", "units") == "Pa", &
            "xdmf/stress_xx units")
        call check(suite, .not. has_link(file, "xdmf/stress_yz"), "no 3D view in 2D")
        values = read_reals(file, "particles/mass", [n])
        call check(suite, all(values(:, 1) == particles%mass), "mass values")
        call check(suite, attribute_text(file, "particles/mass", "units") == "kg/m", &
            "2D mass units per metre")
        values = read_reals(file, "particles/volume", [n])
        call check(suite, all(values(:, 1) == particles%volume), "volume values")
        call check(suite, attribute_text(file, "particles/volume", "units") == "m2", &
            "2D volume units")

        values = read_reals(file, "grid/position", [3, 20])
        call check(suite, all(values(:, 1) == [1.0_wp, -1.0_wp, 0.0_wp]), "grid node 1")
        call check(suite, all(values(:, 2) == [1.5_wp, -1.0_wp, 0.0_wp]), "grid node 2 (x fastest)")
        call check(suite, all(values(:, 20) == [3.0_wp, 0.5_wp, 0.0_wp]), "grid last node")
        values = read_reals(file, "grid/mass", [20])
        call check(suite, all(values(:, 1) == grid%mass), "grid mass")
        values = read_reals(file, "grid/velocity", [3, 20])
        call check(suite, all(values(1:2, :) == grid%velocity) .and. &
            all(values(3, :) == 0.0_wp), "grid velocity")
        call h5fclose_f(file, hdferr)
        call check(suite, hdferr == 0, "close particles_000001.h5")

        xdmf = read_text(dir//"/tiny.xdmf")
        call check_contains(suite, xdmf, '<Xdmf Version="3.0"', "xdmf version")
        call check_contains(suite, xdmf, 'CollectionType="Temporal"', "xdmf temporal collection")
        call check_contains(suite, xdmf, ">particles_000000.h5:/particles/position<", &
            "xdmf lists file 0 (relative path)")
        call check_contains(suite, xdmf, ">particles_000001.h5:/particles/position<", &
            "xdmf lists file 1 (relative path)")
        call check_contains(suite, xdmf, '<Time Value="0.0000000000000000E+000"/>', "time 0")
        call check_contains(suite, xdmf, '<Time Value="2.5000000000000000E-001"/>', "time 0.25")
        call check_contains(suite, xdmf, 'NumberOfElements="5"', "number of particles")
        call check_contains(suite, xdmf, 'Name="stress_xy"', "stress_xy component")
        call check_contains(suite, xdmf, '<DataItem Dimensions="5" NumberType="Float" '// &
            'Precision="8" Format="HDF">particles_000001.h5:/xdmf/stress_xy<', &
            "stress_xy is read from its view")
        call check(suite, index(xdmf, "|") == 0, "no XDMF 3 hyperslab path (XDMFReader fails)")
        call check_contains(suite, xdmf, 'NumberOfElements="5" NodesPerElement="1">', &
            "the Polyvertex topology has a connectivity")
        call check_contains(suite, xdmf, '<DataItem Dimensions="5" NumberType="Int" Precision="'// &
            int_text(storage_size(0)/8)//'" Format="HDF">particles_000001.h5:/xdmf/vertices<', &
            "the connectivity is read from /xdmf/vertices (Xdmf3ReaderS makes no cell without)")
        call check_contains(suite, xdmf, 'Dimensions="1 4 5 3" NumberType="Float" Precision="8" '// &
            'Format="HDF">particles_000001.h5:/grid/velocity<', &
            "grid velocity has the shape of the mesh (z y x, 3)")
        call check_contains(suite, xdmf, 'Dimensions="1 4 5" NumberType="Float" Precision="8" '// &
            'Format="HDF">particles_000001.h5:/grid/mass<', "grid mass has the shape of the mesh")
        call check_contains(suite, xdmf, 'Dimensions="1 4 5"/>', "grid dimensions z y x")
        call check(suite, index(xdmf, dir) == 0, "xdmf has no absolute path")
        call check(suite, count_of(xdmf, 'GridType="Uniform"') == 4, "2 particle + 2 grid grids")
        call check(suite, count_of(xdmf, 'CollectionType="Spatial"') == 2, &
            "one spatial collection (particles + grid) per time")
        call check(suite, index(xdmf, "stress_yz") == 0, "no 3D component in 2D")
    end subroutine test_output_2d

    !> 3D, some fields off, no grid.
    subroutine test_output_3d(suite, dir)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: dir

        type(case_type) :: case
        type(particles_type) :: particles
        type(grid_type) :: grid
        type(output_writer_type) :: writer
        type(error_type), allocatable :: error
        integer(hid_t) :: file
        integer, parameter :: n = 4
        integer :: hdferr
        logical :: exists
        real(wp), allocatable :: values(:, :)
        character(len=:), allocatable :: xdmf

        call tiny_case(case)
        case%name = "cube"
        case%dim = 3
        case%domain%ncells = [2, 3, 4]
        case%output%fields(output_field_index("displacement")) = .false.
        case%output%fields(output_field_index("strain")) = .false.
        case%output%grid = .false.
        call fill_particles(suite, case, n, particles)
        call make_directory(dir, error)
        call new_output_writer(writer, case, dir, error)
        call check(suite, .not. allocated(error), "3D new_output_writer")
        ! grid not built: it must not be needed when output_grid is off
        call write_output(writer, 3, 1.0e-3_wp, particles, grid, error)
        call check(suite, .not. allocated(error), "3D write_output without grid")
        if (allocated(error)) write (*, "(a)") error%message

        call h5fopen_f(dir//"/particles_000000.h5", h5f_acc_rdonly_f, file, hdferr)
        call check(suite, hdferr == 0, "open 3D output")
        values = read_reals(file, "particles/position", [3, n])
        call check(suite, all(values == particles%x), "3D position")
        values = read_reals(file, "particles/stress", [6, n])
        call check(suite, all(values == particles%stress), "3D stress")
        call check(suite, attribute_text(file, "particles/stress", "components") == &
            "xx yy zz xy yz zx", "3D stress components")
        call check(suite, attribute_text(file, "particles/mass", "units") == "kg", "3D mass units")
        call check(suite, attribute_text(file, "particles/volume", "units") == "m3", &
            "3D volume units")
        call check(suite, .not. has_link(file, "particles/strain"), "strain off")
        call check(suite, .not. has_link(file, "particles/displacement"), "displacement off")
        call check(suite, .not. has_link(file, "grid"), "no grid group")
        call check(suite, .not. has_link(file, "particles/id"), "no id without particles%id")
        values = read_reals(file, "xdmf/stress_zx", [n])
        call check(suite, all(values(:, 1) == particles%stress(6, :)), &
            "3D xdmf/stress_zx is column 6 of stress")
        call check(suite, .not. has_link(file, "xdmf/strain_xx"), "strain off: no view")
        call h5aexists_f(file, "image", exists, hdferr)
        call check(suite, hdferr == 0 .and. .not. exists, "no image attribute with one image")
        call h5fclose_f(file, hdferr)

        xdmf = read_text(dir//"/cube.xdmf")
        call check_contains(suite, xdmf, 'Name="stress_zx"', "3D stress_zx")
        call check_contains(suite, xdmf, ">particles_000000.h5:/xdmf/stress_zx<", &
            "stress_zx is read from its view")
        call check(suite, index(xdmf, "strain") == 0, "xdmf: no strain")
        call check(suite, index(xdmf, "displacement") == 0, "xdmf: no displacement")
        call check(suite, index(xdmf, 'Name="grid"') == 0, "xdmf: no grid")
        call check(suite, index(xdmf, 'Name="id"') == 0, "xdmf: no id without particles%id")
        call check_contains(suite, xdmf, '<Grid Name="particles" GridType="Collection" '// &
            'CollectionType="Temporal">', "xdmf: particles-only temporal collection")

        ! 3D grid: XDMF lists the node counts slowest first (z y x), nodes are x fastest
        case%output%grid = .true.
        call new_grid(grid, case, error)
        grid%mass = 1.0_wp
        grid%velocity = 0.0_wp
        grid%velocity(3, :) = -1.0_wp
        call make_directory(dir//"_grid", error)
        call new_output_writer(writer, case, dir//"_grid", error)
        call write_output(writer, 3, 1.0e-3_wp, particles, grid, error)
        call check(suite, .not. allocated(error), "3D write_output with grid")
        call h5fopen_f(dir//"_grid/particles_000000.h5", h5f_acc_rdonly_f, file, hdferr)
        values = read_reals(file, "grid/position", [3, 60])
        call check(suite, all(values(:, 2) - values(:, 1) == [0.5_wp, 0.0_wp, 0.0_wp]), &
            "3D grid: x fastest")
        call check(suite, all(values(:, 60) == [2.0_wp, 0.5_wp, 2.0_wp]), "3D grid: last node")
        values = read_reals(file, "grid/velocity", [3, 60])
        call check(suite, all(values(3, :) == -1.0_wp), "3D grid velocity not padded")
        call h5fclose_f(file, hdferr)
        xdmf = read_text(dir//"_grid/cube.xdmf")
        call check_contains(suite, xdmf, 'TopologyType="3DCoRectMesh" Dimensions="5 4 3"', &
            "3D grid dimensions z y x")
        call check_contains(suite, xdmf, &
            ">0.0000000000000000E+000 -1.0000000000000000E+000 1.0000000000000000E+000<", &
            "3D grid origin z y x")
    end subroutine test_output_3d

    !> n particles of one image, whose ids in the whole run are first, first + 1, ...
    subroutine image_particles(case, n, first, particles)
        type(case_type), intent(in) :: case
        integer, intent(in) :: n, first
        type(particles_type), intent(out) :: particles

        integer :: p

        call fill_particles(suite, case, n, particles)
        particles%id = [(first + p - 1, p = 1, n)]
    end subroutine image_particles

    !> Two images in one process: two writers (image 1 and 2 of 2) on one folder, each with
    !> its own particles and grid slab, as the images of a decomposed run write them.
    subroutine test_output_parts(suite, dir)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: dir

        type(case_type) :: case, slab(2)
        type(particles_type) :: particles(2)
        type(grid_type) :: grid(2)
        type(output_writer_type) :: writer(2), single
        type(error_type), allocatable :: error
        integer(i8) :: counts(2)
        real(wp) :: origins(3, 2)
        integer :: nns(3, 2), k, hdferr, unit, output, part
        integer(hid_t) :: file
        integer, allocatable :: ints(:)
        real(wp), allocatable :: values(:, :)
        character(len=:), allocatable :: xdmf, time0, time1, time2, name

        ! the grid slabs of the images, cells 0-2 and 2-3 in x (each with its ghost cell); of
        ! different sizes, so the index must take each part's grid from its own column
        call tiny_case(case)
        slab = case
        slab(1)%domain%ncells = [3, 3, 1]
        slab(2)%domain%ncells = [2, 3, 1]
        slab(2)%domain%origin(1) = 2.0_wp
        do k = 1, 2
            call new_grid(grid(k), slab(k), error)
            call check(suite, .not. allocated(error), "new_grid of a slab")
            grid(k)%mass = real(k, wp)
            grid(k)%velocity = 0.0_wp
            origins(:, k) = grid(k)%origin
            nns(:, k) = grid(k)%nn
        end do
        call image_particles(case, 3, 1, particles(1))
        call image_particles(case, 2, 4, particles(2))
        counts = [3_i8, 2_i8]
        call make_directory(dir, error)

        ! refusals: nothing is written and the output index does not move
        call new_output_writer(writer(1), case, dir, error, image=3, images=2)
        call check(suite, allocated(error), "image 3 of 2 refused")
        if (allocated(error)) call check_contains(suite, error%message, "image 3", &
            "image out of range message")
        do k = 1, 2
            call new_output_writer(writer(k), case, dir, error, image=k, images=2)
            call check(suite, .not. allocated(error), "new_output_writer of an image")
        end do
        call write_output(writer(1), 0, 0.0_wp, particles(1), grid(1), error)
        call check(suite, allocated(error), "2 images without counts refused")
        if (allocated(error)) call check_contains(suite, error%message, "particle counts", &
            "missing counts message")
        call write_output(writer(1), 0, 0.0_wp, particles(1), grid(1), error, &
            counts=[2_i8, 3_i8], grid_origins=origins, grid_nns=nns)
        call check(suite, allocated(error), "a count that is not the image's n refused")
        call write_output(writer(1), 0, 0.0_wp, particles(1), grid(1), error, counts=counts)
        call check(suite, allocated(error), "grid output without the grids of the images refused")
        if (allocated(error)) call check_contains(suite, error%message, "grid origins", &
            "missing grids message")
        call write_output(writer(1), 0, 0.0_wp, particles(1), grid(1), error, counts=counts, &
            grid_origins=origins(:, [2, 1]), grid_nns=nns(:, [2, 1]))
        call check(suite, allocated(error), "grid columns of the wrong images refused")
        particles(1)%id = [1, 2]
        call write_output(writer(1), 0, 0.0_wp, particles(1), grid(1), error, counts=counts, &
            grid_origins=origins, grid_nns=nns)
        call check(suite, allocated(error), "ids not one per particle refused")
        particles(1)%id = [1, 2, 3]
        call check(suite, .not. file_exists(dir//"/particles_000000_p00001.h5") .and. &
            .not. file_exists(dir//"/tiny.xdmf"), "nothing written by a refused call")

        ! output 0: 3 + 2 particles; image 2 first, and it writes no index
        call write_output(writer(2), 0, 0.0_wp, particles(2), grid(2), error, counts=counts, &
            grid_origins=origins, grid_nns=nns)
        call check(suite, .not. allocated(error), "image 2 writes output 0")
        if (allocated(error)) write (*, "(a)") error%message
        call check(suite, file_exists(dir//"/particles_000000_p00002.h5"), "part 2 of output 0")
        call check(suite, .not. file_exists(dir//"/tiny.xdmf") .and. &
            .not. file_exists(dir//"/tiny.xdmf.tmp"), "image 2 writes no XDMF index")
        call write_output(writer(1), 0, 0.0_wp, particles(1), grid(1), error, counts=counts, &
            grid_origins=origins, grid_nns=nns)
        call check(suite, .not. allocated(error), "image 1 writes output 0")
        if (allocated(error)) write (*, "(a)") error%message
        call check(suite, file_exists(dir//"/particles_000000_p00001.h5"), "part 1 of output 0")
        call check(suite, file_exists(dir//"/tiny.xdmf"), "image 1 writes the XDMF index")

        ! output 1: every particle on image 1, none on image 2 (its part has empty datasets)
        call image_particles(case, 5, 1, particles(1))
        call image_particles(case, 0, 6, particles(2))
        counts = [5_i8, 0_i8]
        do k = 1, 2
            call write_output(writer(k), 7, 0.25_wp, particles(k), grid(k), error, &
                counts=counts, grid_origins=origins, grid_nns=nns)
            call check(suite, .not. allocated(error), "output 1 of image "//int_text(k))
            if (allocated(error)) write (*, "(a)") error%message
        end do
        ! output 2: no particle anywhere
        call image_particles(case, 0, 1, particles(1))
        counts = 0
        do k = 2, 1, -1
            call write_output(writer(k), 9, 0.5_wp, particles(k), grid(k), error, &
                counts=counts, grid_origins=origins, grid_nns=nns)
            call check(suite, .not. allocated(error), "output 2 of image "//int_text(k))
        end do
        call check(suite, .not. file_exists(dir//"/particles_000000.h5"), &
            "no single-image file name with 2 images")
        call check(suite, .not. file_exists(dir//"/particles_000001_p00002.h5.tmp"), &
            "no part .tmp left")
        call check(suite, open_hdf5_objects() == 0, "parts leave no HDF5 object open")

        ! the parts, read back
        call h5fopen_f(dir//"/particles_000000_p00001.h5", h5f_acc_rdonly_f, file, hdferr)
        call check(suite, hdferr == 0, "open part 1 of output 0")
        call check(suite, has_dims(file, "particles/position", [3, 3]), "part 1: 3 particles")
        ints = read_ints(file, "particles/id", 3)
        call check(suite, all(ints == [1, 2, 3]), "part 1: ids")
        call check(suite, attribute_text(file, "particles/id", "units") == "-", "id units")
        call check(suite, attribute_int(file, ".", "image") == 1 .and. &
            attribute_int(file, ".", "images") == 2, "part 1: image 1 of 2")
        call check(suite, has_dims(file, "grid/position", [3, 16]), "part 1: its own grid")
        call h5fclose_f(file, hdferr)
        call h5fopen_f(dir//"/particles_000000_p00002.h5", h5f_acc_rdonly_f, file, hdferr)
        call check(suite, hdferr == 0, "open part 2 of output 0")
        call check(suite, has_dims(file, "particles/position", [3, 2]), "part 2: 2 particles")
        ints = read_ints(file, "particles/id", 2)
        call check(suite, all(ints == [4, 5]), "part 2: ids")
        call check(suite, attribute_int(file, ".", "image") == 2, "part 2: image 2")
        values = read_reals(file, "grid/position", [3, 12])
        call check(suite, all(values(:, 1) == [2.0_wp, -1.0_wp, 0.0_wp]), &
            "part 2: first node of its slab")
        call h5fclose_f(file, hdferr)
        call h5fopen_f(dir//"/particles_000001_p00002.h5", h5f_acc_rdonly_f, file, hdferr)
        call check(suite, hdferr == 0, "open the part without particles")
        call check(suite, has_dims(file, "particles/position", [3, 0]) .and. &
            has_dims(file, "particles/stress", [4, 0]) .and. &
            has_dims(file, "particles/id", [0]) .and. has_dims(file, "xdmf/vertices", [0]) .and. &
            has_dims(file, "xdmf/stress_xy", [0]), "part without particles: empty datasets")
        call check(suite, has_dims(file, "grid/mass", [12]), "part without particles: grid")
        call h5fclose_f(file, hdferr)

        ! the index: one spatial collection of the parts per time
        xdmf = read_text(dir//"/tiny.xdmf")
        call check(suite, count_of(xdmf, 'CollectionType="Temporal"') == 1 .and. &
            count_of(xdmf, 'CollectionType="Spatial"') == 3, "one series, 3 times")
        time0 = between(xdmf, 'Name="output_0"', 'Name="output_1"')
        time1 = between(xdmf, 'Name="output_1"', 'Name="output_2"')
        time2 = between(xdmf, 'Name="output_2"', "</Domain>")
        call check(suite, count_of(time0, '<Grid Name="particles" GridType="Uniform">') == 2 &
            .and. count_of(time0, '<Grid Name="grid" GridType="Uniform">') == 2, &
            "time 0: particles and grid of both parts")
        call check_contains(suite, time0, '<Time Value="0.0000000000000000E+000"/>', "time 0")
        call check_contains(suite, time0, 'NumberOfElements="3"', "time 0: 3 in part 1")
        call check_contains(suite, time0, 'NumberOfElements="2"', "time 0: 2 in part 2")
        call check_contains(suite, time0, '"3 3" NumberType="Float" Precision="8" Format="HDF"'// &
            ">particles_000000_p00001.h5:/particles/position<", "time 0: part 1 positions")
        call check_contains(suite, time0, '"2 3" NumberType="Float" Precision="8" Format="HDF"'// &
            ">particles_000000_p00002.h5:/particles/position<", "time 0: part 2 positions")
        call check_contains(suite, time0, ">particles_000000_p00002.h5:/xdmf/stress_xy<", &
            "time 0: stress_xy of part 2")
        call check_contains(suite, time0, ">particles_000000_p00002.h5:/xdmf/vertices<", &
            "time 0: vertices of part 2")
        call check_contains(suite, time0, '<Attribute Name="id" AttributeType="Scalar"', &
            "id attribute")
        call check_contains(suite, time0, '"2" NumberType="Int" Precision="'// &
            int_text(storage_size(0)/8)//'" Format="HDF">particles_000000_p00002.h5:'// &
            "/particles/id<", "id of part 2 is an integer dataset")
        call check_contains(suite, time0, 'TopologyType="3DCoRectMesh" Dimensions="1 4 4"', &
            "grid of part 1")
        call check_contains(suite, time0, 'TopologyType="3DCoRectMesh" Dimensions="1 4 3"', &
            "grid of part 2")
        call check_contains(suite, time0, &
            ">0.0000000000000000E+000 -1.0000000000000000E+000 2.0000000000000000E+000<", &
            "origin of the grid of part 2 (z y x)")
        call check_contains(suite, time1, '<Time Value="2.5000000000000000E-001"/>', "time 1")
        call check(suite, count_of(time1, '<Grid Name="particles" GridType="Uniform">') == 1 &
            .and. count_of(time1, '<Grid Name="grid" GridType="Uniform">') == 2, &
            "time 1: the part without particles lists its grid only")
        call check_contains(suite, time1, 'NumberOfElements="5"', "time 1: 5 in part 1")
        call check(suite, index(time1, "particles_000001_p00002.h5:/particles/") == 0, &
            "time 1: no particles of the empty part")
        call check_contains(suite, time1, ">particles_000001_p00002.h5:/grid/mass<", &
            "time 1: grid of the empty part")
        call check(suite, count_of(time2, '<Grid Name="particles" GridType="Uniform">') == 1 &
            .and. index(time2, "particles_000002_p00001.h5:/particles/position") > 0 .and. &
            index(time2, 'NumberOfElements="0"') > 0 .and. &
            index(time2, "particles_000002_p00002.h5:/particles/") == 0, &
            "time 2, no particle anywhere: part 1 listed with 0 particles")
        call check(suite, index(xdmf, dir) == 0, "parts: xdmf has no absolute path")

        ! remove_outputs: the parts of every index and image, also of an image that got
        ! further (index 3 of image 2), a .tmp of a killed write, and a single-image run
        call write_output(writer(2), 11, 0.75_wp, particles(2), grid(2), error, &
            counts=counts, grid_origins=origins, grid_nns=nns)
        call check(suite, file_exists(dir//"/particles_000003_p00002.h5"), "part 2 of output 3")
        open (newunit=unit, file=dir//"/particles_000004_p00001.h5.tmp", status="replace", &
            action="write")
        write (unit, "(a)") "killed"
        close (unit)
        open (newunit=unit, file=dir//"/notes.txt", status="replace", action="write")
        write (unit, "(a)") "not an output"
        close (unit)
        call new_output_writer(single, case, dir, error)
        call image_particles(case, 2, 1, particles(1))
        call write_output(single, 0, 0.0_wp, particles(1), grid(1), error)
        call check(suite, .not. allocated(error) .and. &
            file_exists(dir//"/particles_000000.h5"), "a single-image output in the folder")
        call remove_outputs(dir, "tiny", error)
        call check(suite, .not. allocated(error), "remove_outputs")
        if (allocated(error)) write (*, "(a)") error%message
        call check(suite, .not. file_exists(dir//"/tiny.xdmf"), "remove_outputs: index")
        do output = 0, 4
            do part = 0, 2
                name = dir//"/particles_00000"//int_text(output)
                if (part > 0) name = name//"_p0000"//int_text(part)
                name = name//".h5"
                call check(suite, .not. (file_exists(name) .or. file_exists(name//".tmp")), &
                    "remove_outputs: "//name)
            end do
        end do
        call check(suite, file_exists(dir//"/notes.txt"), "remove_outputs: other files stay")
    end subroutine test_output_parts

    ! ----------------------------------------------------------------------------------------
    ! Independent readers (plain HDF5 API)
    ! ----------------------------------------------------------------------------------------

    !> A real dataset of Fortran shape `dims` (1 or 2 entries), as a 2D array (dims, 1) for 1D.
    function read_reals(file, name, dims) result(values)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: name
        integer, intent(in) :: dims(:)
        real(wp), allocatable, target :: values(:, :)

        integer(hid_t) :: dataset, space
        integer(hsize_t) :: file_dims(2), max_dims(2)
        integer :: hdferr, rank
        type(c_ptr) :: buffer

        if (size(dims) == 1) then
            allocate (values(dims(1), 1))
        else
            allocate (values(dims(1), dims(2)))
        end if
        values = -huge(1.0_wp)
        call h5dopen_f(file, name, dataset, hdferr)
        call check(suite, hdferr == 0, "open dataset "//name)
        if (hdferr /= 0) return
        call h5dget_space_f(dataset, space, hdferr)
        call h5sget_simple_extent_ndims_f(space, rank, hdferr)
        call check(suite, rank == size(dims), "rank of "//name)
        if (rank == size(dims)) then
            call h5sget_simple_extent_dims_f(space, file_dims(1:rank), max_dims(1:rank), hdferr)
            call check(suite, all(int(file_dims(1:rank)) == dims), "dimensions of "//name)
            if (all(int(file_dims(1:rank)) == dims)) then
                buffer = c_loc(values)
                call h5dread_f(dataset, h5kind_to_type(wp, h5_real_kind), buffer, hdferr)
                call check(suite, hdferr == 0, "read "//name)
            end if
        end if
        call h5sclose_f(space, hdferr)
        call h5dclose_f(dataset, hdferr)
    end function read_reals

    function read_ints(file, name, n) result(values)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: name
        integer, intent(in) :: n
        integer, allocatable, target :: values(:)

        integer(hid_t) :: dataset
        integer :: hdferr
        type(c_ptr) :: buffer

        allocate (values(n))
        values = -1
        call h5dopen_f(file, name, dataset, hdferr)
        call check(suite, hdferr == 0, "open dataset "//name)
        if (hdferr /= 0) return
        buffer = c_loc(values)
        call h5dread_f(dataset, h5kind_to_type(kind(values), h5_integer_kind), buffer, hdferr)
        call check(suite, hdferr == 0, "read "//name)
        call h5dclose_f(dataset, hdferr)
    end function read_ints

    real(wp) function attribute_real(file, object, name) result(value)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: object, name

        integer(hid_t) :: attribute
        integer :: hdferr
        real(wp), target :: buffer(1)
        type(c_ptr) :: pointer

        buffer = -huge(1.0_wp)
        call h5aopen_by_name_f(file, object, name, attribute, hdferr)
        call check(suite, hdferr == 0, "open attribute "//name)
        if (hdferr == 0) then
            pointer = c_loc(buffer)
            call h5aread_f(attribute, h5kind_to_type(wp, h5_real_kind), pointer, hdferr)
            call h5aclose_f(attribute, hdferr)
        end if
        value = buffer(1)
    end function attribute_real

    integer function attribute_int(file, object, name) result(value)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: object, name

        integer(hid_t) :: attribute
        integer :: hdferr
        integer, target :: buffer(1)
        type(c_ptr) :: pointer

        buffer = -huge(1)
        call h5aopen_by_name_f(file, object, name, attribute, hdferr)
        call check(suite, hdferr == 0, "open attribute "//name)
        if (hdferr == 0) then
            pointer = c_loc(buffer)
            call h5aread_f(attribute, h5kind_to_type(kind(buffer), h5_integer_kind), pointer, &
                hdferr)
            call h5aclose_f(attribute, hdferr)
        end if
        value = buffer(1)
    end function attribute_int

    !> String attribute (element `item` of a 1D one), read as up to 64 null-padded bytes.
    function attribute_text(file, object, name, item) result(value)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: object, name
        integer, intent(in), optional :: item
        character(len=:), allocatable :: value

        integer, parameter :: width = 64
        integer(hid_t) :: attribute, memory_type, space
        integer(hsize_t) :: dims(1), max_dims(1)
        integer :: hdferr, rank, count, i, cut
        character(kind=c_char, len=width), allocatable, target :: buffer(:)
        type(c_ptr) :: pointer

        value = "<missing>"
        call h5aopen_by_name_f(file, object, name, attribute, hdferr)
        call check(suite, hdferr == 0, "open attribute "//object//" "//name)
        if (hdferr /= 0) return
        call h5aget_space_f(attribute, space, hdferr)
        call h5sget_simple_extent_ndims_f(space, rank, hdferr)
        count = 1
        if (rank == 1) then
            call h5sget_simple_extent_dims_f(space, dims, max_dims, hdferr)
            count = int(dims(1))
        end if
        call h5sclose_f(space, hdferr)
        allocate (buffer(count))
        call h5tcopy_f(h5t_fortran_s1, memory_type, hdferr)
        call h5tset_size_f(memory_type, int(width, size_t), hdferr)
        call h5tset_strpad_f(memory_type, h5t_str_nullpad_f, hdferr)
        pointer = c_loc(buffer)
        call h5aread_f(attribute, memory_type, pointer, hdferr)
        call check(suite, hdferr == 0, "read attribute "//name)
        call h5tclose_f(memory_type, hdferr)
        call h5aclose_f(attribute, hdferr)
        i = 1
        if (present(item)) i = item
        if (i > count) return
        cut = index(buffer(i), c_null_char)
        if (cut == 0) cut = width + 1
        value = buffer(i)(1:cut - 1)
    end function attribute_text

    !> Whether a dataset has the Fortran shape `expected` (HDF5 lists it reversed).
    logical function has_dims(file, name, expected)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: name
        integer, intent(in) :: expected(:)

        integer(hid_t) :: dataset, space
        integer(hsize_t) :: dims(7), max_dims(7)
        integer :: hdferr, rank

        has_dims = .false.
        call h5dopen_f(file, name, dataset, hdferr)
        call check(suite, hdferr == 0, "open dataset "//name)
        if (hdferr /= 0) return
        call h5dget_space_f(dataset, space, hdferr)
        call h5sget_simple_extent_ndims_f(space, rank, hdferr)
        if (rank == size(expected)) then
            call h5sget_simple_extent_dims_f(space, dims(1:rank), max_dims(1:rank), hdferr)
            has_dims = all(int(dims(1:rank)) == expected)
        end if
        call h5sclose_f(space, hdferr)
        call h5dclose_f(dataset, hdferr)
    end function has_dims

    !> Whether a dataset is virtual (a view of other datasets, storing no values).
    logical function is_virtual(file, name)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: name

        integer(hid_t) :: dataset, plist
        integer :: hdferr, layout

        is_virtual = .false.
        call h5dopen_f(file, name, dataset, hdferr)
        call check(suite, hdferr == 0, "open dataset "//name)
        if (hdferr /= 0) return
        call h5dget_create_plist_f(dataset, plist, hdferr)
        call h5pget_layout_f(plist, layout, hdferr)
        is_virtual = hdferr == 0 .and. layout == h5d_virtual_f
        call h5pclose_f(plist, hdferr)
        call h5dclose_f(dataset, hdferr)
    end function is_virtual

    logical function has_link(file, path)
        integer(hid_t), intent(in) :: file
        character(len=*), intent(in) :: path

        integer :: hdferr, slash
        logical :: exists

        ! h5lexists_f needs every parent to exist
        has_link = .false.
        slash = index(path, "/")
        if (slash > 0) then
            call h5lexists_f(file, path(1:slash - 1), exists, hdferr)
            if (.not. exists) return
        end if
        call h5lexists_f(file, path, exists, hdferr)
        has_link = exists
    end function has_link

    !> Whole text file as one string, lines joined by new_line.
    function read_text(path) result(text)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: text

        integer :: unit, stat
        character(len=1000) :: line
        character(len=200) :: message

        text = ""
        open (newunit=unit, file=path, status="old", action="read", iostat=stat, iomsg=message)
        call check(suite, stat == 0, "open "//path//": "//trim(message))
        if (stat /= 0) return
        do
            read (unit, "(a)", iostat=stat, iomsg=message) line
            if (stat /= 0) exit
            text = text//trim(line)//new_line("a")
        end do
        close (unit)
    end function read_text

    !> The part of `text` from `first` up to `last` (to the end when `last` is missing).
    function between(text, first, last) result(part)
        character(len=*), intent(in) :: text, first, last
        character(len=:), allocatable :: part

        integer :: start, length

        part = ""
        start = index(text, first)
        call check(suite, start > 0, "found '"//first//"'")
        if (start == 0) return
        length = index(text(start:), last) - 1
        if (length < 0) length = len(text) - start + 1
        part = text(start:start + length - 1)
    end function between

    integer function count_of(text, part)
        character(len=*), intent(in) :: text, part

        integer :: start, found

        count_of = 0
        start = 1
        do
            found = index(text(start:), part)
            if (found == 0) exit
            count_of = count_of + 1
            start = start + found + len(part) - 1
        end do
    end function count_of

end program test_mpm_output
