!> Particle (and optional grid) output: one HDF5 file per output time plus one XDMF index.
!>
!> Each call of `write_output` writes `<dir>/particles_<NNNNNN>.h5` (NNNNNN = output index
!> 0, 1, 2, ... zero padded to 6 digits) and then rewrites `<dir>/<case name>.xdmf`, the
!> XDMF 3 time series that ParaView opens. Both are written to a `.tmp` file first and
!> renamed, so a run killed at any moment leaves an index that lists only complete files.
!>
!> A run on several images (domain decomposition) writes one part per image and output,
!> `particles_<NNNNNN>_p<KKKKK>.h5` (KKKKK = image, 5 digits), with that image's particles
!> and grid slab; image 1 alone writes the index, in which each output time is a spatial
!> collection of the parts. The layout of the files is described in docs/output.md. The
!> XDMF index is written by the submodule mpm_output_xdmf.
module mpm_output
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: int_text
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type
    use mpm_case_output_fields, only: output_field_type, output_fields, nfields, layout_vector, &
        layout_voigt, layout_scalar
    use mpm_case_materials, only: writes_plastic_strain
    use mpm_particles, only: particles_type, particle_field_type, particle_field, field_index, &
        field_units, get_field, get_field_integers
    use mpm_grid, only: grid_type, node_position
    use mpm_hdf5, only: hdf5_location_type, text_type, hdf5_initialize, hdf5_create_file, &
        hdf5_create_group, hdf5_close_after, hdf5_write_dataset, hdf5_write_attribute, &
        hdf5_write_column_view
    use mpm_filesystem, only: directory_exists, rename_file, remove_file, file_exists, &
        text_file_type, open_text_file, put_line, close_text_file
    use mpm_version, only: mpm_version_string
    implicit none
    private
    public :: output_list, resume_output_writer, output_count
    public :: output_writer_type, new_output_writer, write_output, write_index, remove_outputs, &
        write_terrain

    integer, parameter :: max_images = 99999
        !! most images a part file name can number (5 digits)

    !> One output time already written (one file, or one part per image).
    type :: output_record_type
        real(wp) :: time = 0.0_wp
            !! simulated time of the output [s]
        integer :: step = 0
            !! time step number of the output
        integer(i8), allocatable :: counts(:)
            !! number of particles in the file of each image (images)
        logical :: id = .false.
            !! the files hold /particles/id
    end type output_record_type

    !> Writer of the output files of one run; create it with new_output_writer.
    type :: output_writer_type
        private
        character(len=:), allocatable :: dir
            !! output folder, without trailing '/'
        character(len=:), allocatable :: case_name
            !! case name, also the name of the XDMF file
        integer :: dim = 2
            !! space dimensions
        logical :: fields(nfields) = .true.
            !! fields to write (position is always written)
        logical :: grid = .false.
            !! also write the grid nodes
        type(text_type), allocatable :: materials(:)
            !! material names in case order (material index i is materials(i))
        integer :: image = 1
            !! this image, 1 .. images
        integer :: images = 1
            !! number of images; above 1 each image writes its own part files
        integer :: count = 0
            !! number of output times written
        type(output_record_type), allocatable :: records(:)
            !! output times written so far (1:count); kept by image 1 only, which writes the
            !! index
        integer, allocatable :: grid_nn(:, :)
            !! nodes per direction of the grid of each image (3, images); the grids do not
            !! change during a run
        real(wp), allocatable :: grid_origin(:, :)
            !! position of the first node of the grid of each image (3, images), z = 0 in 2D [m]
        real(wp) :: grid_dx = 0.0_wp
            !! grid spacing [m]
    end type output_writer_type

    character(len=*), parameter :: components_2d = "xx yy zz xy"
        !! Voigt components stored in 2D
    character(len=*), parameter :: components_3d = "xx yy zz xy yz zx"
        !! Voigt components stored in 3D
    character(len=*), parameter :: voigt_components(6) = &
        [character(len=2) :: "xx", "yy", "zz", "xy", "yz", "zx"]
        !! names of the Voigt components, in the order of the columns

    ! The submodule mpm_output_xdmf: the index, and the helpers this module calls too (file
    ! names, XDMF data items), declared as separate module procedures: gfortran's link-time
    ! optimisation drops a private procedure of a module that a submodule calls.
    interface
        !> Rewrite <dir>/<case>.xdmf listing every file written so far (submodule
        !> mpm_output_xdmf).
        module subroutine write_xdmf(writer, error)
            type(output_writer_type), intent(in) :: writer
                !! writer of image 1, with the records of every output time
            type(error_type), allocatable, intent(out) :: error
                !! set when the index cannot be written
        end subroutine write_xdmf
        !> An XDMF DataItem pointing to an HDF5 dataset.
        module pure function data_item(dims, number_type, source) result(text)
            character(len=*), intent(in) :: dims
                !! dimensions, slowest first ("n 3")
            character(len=*), intent(in) :: number_type
                !! "Float" (8 bytes) or "Int" (default integer)
            character(len=*), intent(in) :: source
                !! "file.h5:/group/dataset"
            character(len=:), allocatable :: text
        end function data_item
        !> Whether output field i is written as a dataset of /particles and an attribute of
        !> the index: listed by the case, and not the positions (the geometry).
        module pure function attribute(writer, i) result(listed)
            type(output_writer_type), intent(in) :: writer
                !! the run's writer
            integer, intent(in) :: i
                !! index in output_fields
            logical :: listed
                !! written as a dataset and an attribute
        end function attribute
        !> Name of the particle file of output number `index` (0-based).
        module pure function particle_file_name(index) result(name)
            integer, intent(in) :: index
                !! output index
            character(len=:), allocatable :: name
                !! "particles_NNNNNN.h5"
        end function particle_file_name
        !> Name of the file of one image at output number `index` (0-based): the particle file
        !> itself for a single image, a part file for several.
        module pure function part_file_name(index, image, images) result(name)
            integer, intent(in) :: index
                !! output index
            integer, intent(in) :: image
                !! image, 1 .. images
            integer, intent(in) :: images
                !! number of images
            character(len=:), allocatable :: name
                !! "particles_NNNNNN.h5" (one image) or "particles_NNNNNN_pKKKKK.h5"
        end function part_file_name
    end interface

contains

    !> Record the output settings of a case; no file is written yet.
    subroutine new_output_writer(writer, case, dir, error, image, images)
        type(output_writer_type), intent(out) :: writer
            !! writer to create
        type(case_type), intent(in) :: case
            !! resolved case (name, dim, output_fields, output_grid, materials)
        character(len=*), intent(in) :: dir
            !! existing output folder (created by the caller)
        type(error_type), allocatable, intent(out) :: error
            !! set when the folder does not exist, HDF5 cannot start or the images are wrong
        integer, intent(in), optional :: image
            !! this image, 1 .. images (default 1)
        integer, intent(in), optional :: images
            !! number of images of the run (default 1: one file per output, no parts)

        integer :: i, last, m
        logical :: plastic

        if (case%dim /= 2 .and. case%dim /= 3) then
            call fatal_error(error, "output: the case has dimension "//int_text(case%dim)// &
                ", expected 2 or 3", exit_other)
            return
        end if
        writer%image = 1
        if (present(image)) writer%image = image
        writer%images = 1
        if (present(images)) writer%images = images
        if (writer%images < 1 .or. writer%images > max_images) then
            call fatal_error(error, "output: "//int_text(writer%images)//" images, expected "// &
                "1 to "//int_text(max_images), exit_other)
            return
        end if
        if (writer%image < 1 .or. writer%image > writer%images) then
            call fatal_error(error, "output: image "//int_text(writer%image)// &
                " is not one of the images 1 to "//int_text(writer%images), exit_other)
            return
        end if
        if (.not. directory_exists(dir)) then
            call fatal_error(error, "the output folder '"//dir//"' does not exist", exit_other)
            return
        end if
        call hdf5_initialize(error)
        if (allocated(error)) return

        last = len_trim(dir)
        do while (last > 1)
            if (dir(last:last) /= "/") exit
            last = last - 1
        end do
        writer%dir = dir(1:last)
        if (allocated(case%name)) then
            writer%case_name = case%name
        else
            writer%case_name = "case"
        end if
        if (len(writer%case_name) == 0) writer%case_name = "case"
        writer%dim = case%dim
        writer%fields = case%output%fields
        ! the accumulated plastic shear strain exists only where a material is plastic
        plastic = .false.
        do m = 1, size(case%materials)
            plastic = plastic .or. writes_plastic_strain(case%materials(m))
        end do
        where (output_fields%plastic) writer%fields = writer%fields .and. plastic
        ! the pore pressure, effective stress and water velocity of saturated soils
        where (output_fields%water) writer%fields = writer%fields .and. case%pore_water%on
        writer%grid = case%output%grid
        if (allocated(case%materials)) then
            allocate (writer%materials(size(case%materials)))
            do i = 1, size(case%materials)
                writer%materials(i)%text = ""
                if (allocated(case%materials(i)%name)) then
                    writer%materials(i)%text = case%materials(i)%name
                end if
            end do
        else
            allocate (writer%materials(0))
        end if
        allocate (writer%grid_nn(3, writer%images), writer%grid_origin(3, writer%images))
        writer%grid_nn = 1
        writer%grid_origin = 0.0_wp
        allocate (writer%records(merge(16, 0, writer%image == 1)))
        writer%count = 0
    end subroutine new_output_writer

    !> Number of output times written so far (a restart counts those of the earlier run).
    pure integer function output_count(writer)
        type(output_writer_type), intent(in) :: writer
            !! the run's writer
        output_count = writer%count
    end function output_count

    !> The output times written so far, for a checkpoint (image 1 keeps them; the other
    !> images return empty lists).
    subroutine output_list(writer, time, step, counts, id)
        type(output_writer_type), intent(in) :: writer
            !! the run's writer
        real(wp), allocatable, intent(out) :: time(:)
            !! time of each output [s]
        integer, allocatable, intent(out) :: step(:)
            !! step of each output
        integer, allocatable, intent(out) :: counts(:, :)
            !! particles in the file of each image at each output (images, outputs)
        logical, allocatable, intent(out) :: id(:)
            !! the files of each output hold particle ids

        integer :: i, n

        n = 0
        if (writer%image == 1) n = writer%count
        allocate (time(n), step(n), counts(writer%images, n), id(n))
        do i = 1, n
            time(i) = writer%records(i)%time
            step(i) = writer%records(i)%step
            counts(:, i) = int(writer%records(i)%counts)
            id(i) = writer%records(i)%id
        end do
    end subroutine output_list

    !> Continue the outputs of an earlier run of the case (a restart from a checkpoint): the
    !> next output gets the next number, and the index lists the earlier outputs too.
    subroutine resume_output_writer(writer, time, step, counts, id, error)
        type(output_writer_type), intent(inout) :: writer
            !! writer made by new_output_writer, nothing written yet
        real(wp), intent(in) :: time(:)
            !! output_list of the earlier run
        integer, intent(in) :: step(:)
            !! output_list of the earlier run
        integer, intent(in) :: counts(:, :)
            !! output_list of the earlier run (images, outputs)
        logical, intent(in) :: id(:)
            !! output_list of the earlier run
        type(error_type), allocatable, intent(out) :: error
            !! set when the lists do not fit this writer

        integer :: i, n

        n = size(time)
        if (size(step) /= n .or. size(id) /= n .or. size(counts, 2) /= n .or. &
            size(counts, 1) /= writer%images) then
            call fatal_error(error, "output: the outputs of the earlier run do not fit ("// &
                int_text(size(counts, 1))//" images, this run has "// &
                int_text(writer%images)//")", exit_other)
            return
        end if
        writer%count = n
        if (writer%image /= 1) return
        deallocate (writer%records)
        allocate (writer%records(max(16, 2*n)))
        do i = 1, n
            writer%records(i)%time = time(i)
            writer%records(i)%step = step(i)
            writer%records(i)%counts = int(counts(:, i), i8)
            writer%records(i)%id = id(i)
        end do
    end subroutine resume_output_writer

    !> Write the particles (and the grid if the case asks) at one time, then the XDMF index.
    !>
    !> With several images every image calls it at every output time with its own particles
    !> and grid slab; it writes this image's part, and image 1 also rewrites the index, which
    !> lists the parts of all images (from `counts`, `grid_origins` and `grid_nns`).
    subroutine write_output(writer, step, time, particles, grid, error, counts, grid_origins, &
            grid_nns, defer_index)
        type(output_writer_type), intent(inout) :: writer
            !! writer made by new_output_writer
        integer, intent(in) :: step
            !! time step number
        real(wp), intent(in) :: time
            !! simulated time [s]
        type(particles_type), intent(in) :: particles
            !! particles to write (this image's)
        type(grid_type), intent(in) :: grid
            !! grid (this image's slab); written only when the case sets output_grid
        type(error_type), allocatable, intent(out) :: error
            !! set when a file cannot be written (the message names it) or an argument is
            !! missing or inconsistent
        integer(i8), intent(in), optional :: counts(:)
            !! number of particles of every image at this output (images); required when
            !! images > 1, ignored otherwise
        real(wp), intent(in), optional :: grid_origins(:, :)
            !! position of the first node of the grid of every image (3, images) [m];
            !! required when images > 1 and the case writes the grid, ignored otherwise
        integer, intent(in), optional :: grid_nns(:, :)
            !! nodes per direction of the grid of every image (3, images); required when
            !! images > 1 and the case writes the grid, ignored otherwise
        logical, intent(in), optional :: defer_index
            !! do not rewrite the index: the caller calls write_index once every image has
            !! written its part (so the index never names a part that is not complete)

        character(len=:), allocatable :: name, path
        type(output_record_type), allocatable :: grown(:)
        type(output_record_type) :: record
        type(error_type), allocatable :: ignored

        if (.not. allocated(writer%dir)) then
            call fatal_error(error, "write_output called before new_output_writer", exit_other)
            return
        end if
        if (particles%dim /= writer%dim) then
            call fatal_error(error, "output: the particles have dimension "// &
                int_text(particles%dim)//" but the case has "//int_text(writer%dim), exit_other)
            return
        end if
        if (allocated(particles%id)) then
            if (size(particles%id) /= particles%n) then
                call fatal_error(error, "output: "//int_text(size(particles%id))// &
                    " particle ids for "//int_text(particles%n)//" particles", exit_other)
                return
            end if
        end if
        if (writer%grid) then
            if (.not. (allocated(grid%mass) .and. allocated(grid%velocity))) then
                call fatal_error(error, "output: grid output is on but the grid has no "// &
                    "nodal fields (new_grid not called)", exit_other)
                return
            end if
        end if
        if (writer%images > 1) then
            call check_parts(writer, particles, grid, error, counts, grid_origins, grid_nns)
            if (allocated(error)) return
        end if

        name = part_file_name(writer%count, writer%image, writer%images)
        path = writer%dir//"/"//name
        call write_hdf5_file(writer, path, step, time, particles, grid, error)
        if (allocated(error)) then
            ! (the outputs before and their index stay as they were)
            call remove_file(path//".tmp", ignored)
            return
        end if
        call rename_file(path//".tmp", path, error)
        if (allocated(error)) return

        if (writer%grid) then
            writer%grid_dx = grid%dx
            writer%grid_origin = 0.0_wp
            if (writer%images == 1) then
                writer%grid_nn(:, 1) = grid%nn
                writer%grid_origin(1:writer%dim, 1) = grid%origin(1:writer%dim)
            else
                writer%grid_nn = grid_nns
                writer%grid_origin(1:writer%dim, :) = grid_origins(1:writer%dim, :)
            end if
        end if
        writer%count = writer%count + 1
        ! only image 1 writes the index, so only it needs the records
        if (writer%image /= 1) return

        record%time = time
        record%step = step
        if (writer%images == 1) then
            record%counts = [int(particles%n, i8)]
        else
            record%counts = counts
        end if
        record%id = allocated(particles%id)
        if (writer%count > size(writer%records)) then
            allocate (grown(2*size(writer%records)))
            grown(1:writer%count - 1) = writer%records(1:writer%count - 1)
            call move_alloc(grown, writer%records)
        end if
        writer%records(writer%count) = record

        if (present(defer_index)) then
            if (defer_index) return
        end if
        call write_xdmf(writer, error)
    end subroutine write_output

    !> Rewrite the index after write_output(..., defer_index=.true.) (image 1; nothing on the
    !> other images).
    subroutine write_index(writer, error)
        type(output_writer_type), intent(in) :: writer
            !! the writer
        type(error_type), allocatable, intent(out) :: error
            !! set when the index cannot be written

        if (writer%image == 1) call write_xdmf(writer, error)
    end subroutine write_index

    !> The arguments a run on several images must give write_output, checked against this
    !> image's particles and grid.
    subroutine check_parts(writer, particles, grid, error, counts, grid_origins, grid_nns)
        type(output_writer_type), intent(in) :: writer
            !! writer with images > 1
        type(particles_type), intent(in) :: particles
            !! this image's particles
        type(grid_type), intent(in) :: grid
            !! this image's grid
        type(error_type), allocatable, intent(out) :: error
            !! set when an argument is missing or does not fit
        integer(i8), intent(in), optional :: counts(:)
            !! number of particles of every image (images)
        real(wp), intent(in), optional :: grid_origins(:, :)
            !! first node of the grid of every image (3, images) [m]
        integer, intent(in), optional :: grid_nns(:, :)
            !! nodes per direction of the grid of every image (3, images)

        character(len=:), allocatable :: images

        images = int_text(writer%images)
        if (.not. present(counts)) then
            call fatal_error(error, "output: a run on "//images//" images needs the "// &
                "particle counts of every image", exit_other)
            return
        end if
        if (size(counts) /= writer%images) then
            call fatal_error(error, "output: "//int_text(size(counts))//" particle counts "// &
                "for "//images//" images", exit_other)
            return
        end if
        if (any(counts < 0)) then
            call fatal_error(error, "output: a negative particle count", exit_other)
            return
        end if
        if (counts(writer%image) /= particles%n) then
            call fatal_error(error, "output: the count of image "//int_text(writer%image)// &
                " is not its number of particles, "//int_text(particles%n), exit_other)
            return
        end if
        if (.not. writer%grid) return
        if (.not. (present(grid_origins) .and. present(grid_nns))) then
            call fatal_error(error, "output: a run on "//images//" images that writes the "// &
                "grid needs the grid origins and node counts of every image", exit_other)
            return
        end if
        if (any(shape(grid_origins) /= [3, writer%images]) .or. &
            any(shape(grid_nns) /= [3, writer%images])) then
            call fatal_error(error, "output: grid origins and node counts must have the "// &
                "shape (3, "//images//")", exit_other)
            return
        end if
        ! another image's grid starts at least one cell away: half a cell tells them apart
        if (any(grid_nns(:, writer%image) /= grid%nn) .or. &
            any(abs(grid_origins(1:writer%dim, writer%image) - grid%origin(1:writer%dim)) > &
            0.5_wp*grid%dx)) then
            call fatal_error(error, "output: the grid origin or node counts given for image "// &
                int_text(writer%image)//" are not those of its grid", exit_other)
            return
        end if
    end subroutine check_parts

    !> One HDF5 output file: root attributes, /particles and optionally /grid.
    subroutine write_hdf5_file(writer, path, step, time, particles, grid, error)
        type(output_writer_type), intent(in) :: writer
        character(len=*), intent(in) :: path
            !! file to create, written as path.tmp (messages name path)
        integer, intent(in) :: step
        real(wp), intent(in) :: time
        type(particles_type), intent(in) :: particles
        type(grid_type), intent(in) :: grid
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: file

        call hdf5_create_file(path//".tmp", file, error, shown_as=path)
        if (allocated(error)) return
        steps: block
            call hdf5_write_attribute(file, "time", time, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "step", step, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "dimension", writer%dim, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "case_name", writer%case_name, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "mpm_geo_version", mpm_version_string, error)
            if (allocated(error)) exit steps
            call hdf5_write_attribute(file, "material_names", writer%materials, error)
            if (allocated(error)) exit steps
            if (writer%images > 1) then
                call hdf5_write_attribute(file, "image", writer%image, error)
                if (allocated(error)) exit steps
                call hdf5_write_attribute(file, "images", writer%images, error)
                if (allocated(error)) exit steps
            end if
            call write_particles_group(writer, file, particles, error)
            if (allocated(error)) exit steps
            call write_xdmf_group(writer, file, particles%n, error)
            if (allocated(error)) exit steps
            if (writer%grid) call write_grid_group(file, grid, error)
        end block steps
        call hdf5_close_after(file, error)
    end subroutine write_hdf5_file

    !> The /particles group: one row per particle, only the fields the case asks for.
    subroutine write_particles_group(writer, file, particles, error)
        type(output_writer_type), intent(in) :: writer
        type(hdf5_location_type), intent(in) :: file
        type(particles_type), intent(in) :: particles
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: group
        integer :: i

        call hdf5_create_group(file, "particles", group, error)
        if (allocated(error)) return
        steps: block
            call write_vector(group, "position", particles%x, "m", error)
            if (allocated(error)) exit steps
            do i = 1, nfields
                if (.not. attribute(writer, i)) cycle
                call write_field(writer, group, output_fields(i), particles, error)
                if (allocated(error)) exit steps
            end do
            if (allocated(particles%id)) then
                call hdf5_write_dataset(group, "id", particles%id, error, units="-")
                if (allocated(error)) exit steps
            end if
        end block steps
        call hdf5_close_after(group, error)
    end subroutine write_particles_group

    !> One output field as a dataset of /particles (nothing when its source lacks the row).
    subroutine write_field(writer, group, output, particles, error)
        type(output_writer_type), intent(in) :: writer
        type(hdf5_location_type), intent(in) :: group
        type(output_field_type), intent(in) :: output
        type(particles_type), intent(in) :: particles
        type(error_type), allocatable, intent(out) :: error

        type(particle_field_type) :: source
        real(wp), allocatable :: values(:, :), column(:)
        integer, allocatable :: integers(:)
        character(len=:), allocatable :: name, units
        integer :: k

        k = field_index(trim(output%source))
        source = particle_field(k)
        name = trim(output%name)
        units = field_units(source, writer%dim)
        if (source%whole) then
            call get_field_integers(particles, k, integers)
            call hdf5_write_dataset(group, name, integers, error, units=units)
            return
        end if
        call get_field(particles, k, values)
        if (output%row > 0) then
            ! (the plastic strain of particles without material state)
            if (output%row > size(values, 1)) return
            ! (copies, not sections: the dataset writer takes contiguous arrays)
            column = values(output%row, :)
            call hdf5_write_dataset(group, name, column, error, units=units)
        else if (output%layout == layout_vector) then
            call write_vector(group, name, values, units, error)
        else if (output%layout == layout_voigt) then
            call hdf5_write_dataset(group, name, values, error, units=units, &
                components=voigt_text(writer%dim))
        else
            column = values(1, :)
            call hdf5_write_dataset(group, name, column, error, units=units)
        end if
    end subroutine write_field

    !> The /xdmf group: what the XDMF index reads besides /particles, so that both ParaView
    !> readers (Xdmf3ReaderS and XDMFReader) load the index.
    !>
    !> `vertices` (0, 1, ..., n-1) is the Polyvertex connectivity: without it Xdmf3ReaderS
    !> makes no cell, and cell filters (Threshold) keep nothing. `stress_xx`, ..., `strain_..`
    !> are virtual datasets, views of the columns of /particles/stress and /particles/strain:
    !> the readers share no form of column selection (XDMFReader does not read the XDMF 3
    !> hyperslab path, Xdmf3ReaderS skips ItemType="HyperSlab"), and a view stores no value
    !> twice.
    subroutine write_xdmf_group(writer, file, n, error)
        type(output_writer_type), intent(in) :: writer
        type(hdf5_location_type), intent(in) :: file
        integer, intent(in) :: n
            !! number of particles in the file
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: group
        integer :: k, i

        call hdf5_create_group(file, "xdmf", group, error)
        if (allocated(error)) return
        steps: block
            call hdf5_write_dataset(group, "vertices", [(k, k = 0, n - 1)], error, units="-")
            if (allocated(error)) exit steps
            do i = 1, nfields
                if (.not. attribute(writer, i)) cycle
                if (output_fields(i)%layout /= layout_voigt) cycle
                call write_views(trim(output_fields(i)%name), field_units(particle_field( &
                    field_index(trim(output_fields(i)%source))), writer%dim), error)
                if (allocated(error)) exit steps
            end do
        end block steps
        call hdf5_close_after(group, error)

    contains

        !> One view per Voigt component of /particles/<name>: "<name>_xx", ...
        subroutine write_views(name, units, error)
            character(len=*), intent(in) :: name, units
            type(error_type), allocatable, intent(out) :: error

            integer :: c

            ! Voigt order: the first 4 components in 2D, all 6 in 3D
            do c = 1, merge(4, 6, writer%dim == 2)
                call hdf5_write_column_view(group, name//"_"//trim(voigt_components(c)), &
                    "/particles/"//name, c, error, units=units)
                if (allocated(error)) return
            end do
        end subroutine write_views

    end subroutine write_xdmf_group

    !> The /grid group: node positions, nodal mass and velocity.
    subroutine write_grid_group(file, grid, error)
        type(hdf5_location_type), intent(in) :: file
        type(grid_type), intent(in) :: grid
        type(error_type), allocatable, intent(out) :: error

        type(hdf5_location_type) :: group
        real(wp), allocatable :: position(:, :)
        integer :: id, stat
        character(len=256) :: message

        allocate (position(3, grid%nnodes), stat=stat, errmsg=message)
        if (stat /= 0) then
            call fatal_error(error, "output: cannot allocate the grid positions: "// &
                trim(message), exit_other)
            return
        end if
        do id = 1, grid%nnodes
            position(:, id) = node_position(grid, id)
        end do
        if (grid%dim == 2) position(3, :) = 0.0_wp

        call hdf5_create_group(file, "grid", group, error)
        if (allocated(error)) return
        steps: block
            call hdf5_write_dataset(group, "position", position, error, units="m")
            if (allocated(error)) exit steps
            call hdf5_write_dataset(group, "mass", grid%mass, error, units=mass_units(grid%dim))
            if (allocated(error)) exit steps
            call write_vector(group, "velocity", grid%velocity, "m/s", error)
            if (allocated(error)) exit steps
            if (allocated(grid%node_reaction)) then
                call write_vector(group, "reaction", grid%node_reaction, &
                    trim(merge("N  ", "N/m", grid%dim == 3)), error)
            else
                call write_vector(group, "reaction", spread([(0.0_wp, id = 1, grid%dim)], 2, &
                    grid%nnodes), trim(merge("N  ", "N/m", grid%dim == 3)), error)
            end if
        end block steps
        call hdf5_close_after(group, error)
    end subroutine write_grid_group

    !> The terrain surface of a run, for ParaView: `<dir>/terrain.h5` (/terrain/position, the
    !> 3 corners of each triangle, and /terrain/triangles, their 0-based indices) and
    !> `<dir>/terrain.xdmf`, a triangle mesh to open beside the particles' index.
    subroutine write_terrain(dir, corner, error)
        character(len=*), intent(in) :: dir
            !! output folder
        real(wp), intent(in) :: corner(:, :, :)
            !! (3, 3, n) triangle corners, as the run uses them [m]
        type(error_type), allocatable, intent(out) :: error
            !! set when a file cannot be written

        type(hdf5_location_type) :: file, group
        type(error_type), allocatable :: ignored
        type(text_file_type) :: surface_index
        real(wp), allocatable :: position(:, :)
        integer :: n, k, i
        character(len=:), allocatable :: path, nt, nv
        type(text_type), allocatable :: lines(:)

        n = size(corner, 3)
        position = reshape(corner, [3, 3*n])
        path = dir//"/terrain.h5"
        call hdf5_create_file(path//".tmp", file, error, shown_as=path)
        if (allocated(error)) return
        call hdf5_create_group(file, "terrain", group, error)
        if (.not. allocated(error)) then
            call hdf5_write_dataset(group, "position", position, error, units="m")
            if (.not. allocated(error)) call hdf5_write_dataset(group, "triangles", &
                [(k, k = 0, 3*n - 1)], error, units="-")
            call hdf5_close_after(group, error)
        end if
        call hdf5_close_after(file, error)
        if (allocated(error)) then
            call remove_file(path//".tmp", ignored)
            return
        end if
        call rename_file(path//".tmp", path, error)
        if (allocated(error)) return
        nt = int_text(n)
        nv = int_text(3*n)
        path = dir//"/terrain.xdmf"
        lines = [text_type('<?xml version="1.0" ?>'), &
            text_type('<Xdmf Version="3.0">'), &
            text_type("  <Domain>"), &
            text_type('    <Grid Name="terrain" GridType="Uniform">'), &
            text_type('      <Topology TopologyType="Triangle" NumberOfElements="'//nt//'">'), &
            text_type("        "//data_item(nt//" 3", "Int", "terrain.h5:/terrain/triangles")), &
            text_type("      </Topology>"), &
            text_type('      <Geometry GeometryType="XYZ">'), &
            text_type("        "//data_item(nv//" 3", "Float", "terrain.h5:/terrain/position")), &
            text_type("      </Geometry>"), &
            text_type("    </Grid>"), &
            text_type("  </Domain>"), &
            text_type("</Xdmf>")]
        call open_text_file(path, surface_index, error)
        if (allocated(error)) return
        do i = 1, size(lines)
            call put_line(surface_index, lines(i)%text)
        end do
        call close_text_file(surface_index, error)
    end subroutine write_terrain

    !> Write a (dim, n) vector field as an (n, 3) dataset, z = 0 in 2D.
    subroutine write_vector(group, name, values, units, error)
        type(hdf5_location_type), intent(in) :: group
        character(len=*), intent(in) :: name
        real(wp), intent(in), contiguous :: values(:, :)
            !! vectors (dim, n)
        character(len=*), intent(in) :: units
        type(error_type), allocatable, intent(out) :: error

        real(wp), allocatable :: padded(:, :)
        integer :: stat
        character(len=256) :: message

        if (size(values, 1) == 3) then
            call hdf5_write_dataset(group, name, values, error, units=units)
            return
        end if
        allocate (padded(3, size(values, 2)), stat=stat, errmsg=message)
        if (stat /= 0) then
            call fatal_error(error, "output: cannot allocate a copy of "//name//": "// &
                trim(message), exit_other)
            return
        end if
        padded = 0.0_wp
        padded(1:size(values, 1), :) = values
        call hdf5_write_dataset(group, name, padded, error, units=units)
    end subroutine write_vector

    pure function mass_units(dim) result(units)
        integer, intent(in) :: dim
        character(len=:), allocatable :: units

        if (dim == 2) then
            units = "kg/m"
        else
            units = "kg"
        end if
    end function mass_units

    !> The "components" attribute of a Voigt field: "xx yy zz xy" in 2D.
    pure function voigt_text(dim) result(text)
        integer, intent(in) :: dim
        character(len=:), allocatable :: text

        if (dim == 2) then
            text = components_2d
        else
            text = components_3d
        end if
    end function voigt_text

    !> Delete the particle files, part files and the XDMF index an earlier run of a case left
    !> in `dir` (and the `.tmp` files of one that was killed while writing), so an
    !> overwritten folder holds no stale outputs of a longer earlier run or one on more
    !> images. No other file is touched.
    !>
    !> Fortran cannot list a folder, so the names are probed: output indices 0, 1, ... until
    !> one has no file, and at each index the parts of the images 1 .. K, K being the number
    !> of consecutive images with a part (or its .tmp) at index 0.
    subroutine remove_outputs(dir, case_name, error)
        character(len=*), intent(in) :: dir
            !! output folder
        character(len=*), intent(in) :: case_name
            !! case name (names the XDMF index)
        type(error_type), allocatable, intent(out) :: error
            !! set when a file cannot be deleted

        integer :: index, parts, part
        logical :: found

        call remove_file(dir//"/"//case_name//".xdmf", error)
        if (allocated(error)) return
        call remove_file(dir//"/"//case_name//".xdmf.tmp", error)
        if (allocated(error)) return
        ! the terrain of an earlier run (write_terrain)
        call remove_file(dir//"/terrain.xdmf", error)
        if (allocated(error)) return
        call remove_file(dir//"/terrain.h5", error)
        if (allocated(error)) return
        parts = 0
        do
            if (.not. (file_exists(dir//"/"//part_file_name(0, parts + 1, 2)) .or. &
                file_exists(dir//"/"//part_file_name(0, parts + 1, 2)//".tmp"))) exit
            parts = parts + 1
        end do
        index = 0
        do
            found = .false.
            call remove_output(particle_file_name(index), found, error)
            if (allocated(error)) return
            do part = 1, parts
                call remove_output(part_file_name(index, part, 2), found, error)
                if (allocated(error)) return
            end do
            if (.not. found) exit
            index = index + 1
        end do

    contains

        !> Delete one file and its .tmp, noting whether either existed.
        subroutine remove_output(name, found, error)
            character(len=*), intent(in) :: name
                !! file name in the folder
            logical, intent(inout) :: found
                !! set when the file or its .tmp existed
            type(error_type), allocatable, intent(out) :: error
                !! set when a file cannot be deleted

            character(len=:), allocatable :: path

            path = dir//"/"//name
            found = found .or. file_exists(path) .or. file_exists(path//".tmp")
            call remove_file(path, error)
            if (allocated(error)) return
            call remove_file(path//".tmp", error)
        end subroutine remove_output

    end subroutine remove_outputs

end module mpm_output
