!> Unit tests of the cut of the grid among images (mpm_decomposition): the cut axis, slabs
!> that balance the particles of a histogram and keep min_slab_cells each, the refusal of a
!> grid too small for the images, and each image's grid (its slab with the ghost cells, free
!> faces at the cuts, the case's faces elsewhere). Run on one image: the decomposition of
!> any image count is computed, not exchanged.
program test_mpm_decomposition
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, exit_input
    use mpm_testing, only: test_suite_type, new_suite, check, check_contains, finish
    use mpm_case, only: case_type, read_case_string
    use mpm_decomposition, only: decomposition_type, cut_axis, new_decomposition, local_case, &
        global_cell, min_slab_cells, image_grids
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_decomposition")
    call test_axis_and_cells()
    call test_balance()
    call test_uniform_and_empty()
    call test_too_few_cells()
    call test_local_grids()
    call finish(suite)

contains

    !> A 2D case of nx x ny cells of 0.5 m from (-1, 2), its faces fixed (x) and sliding (y).
    subroutine grid_case(nx, ny, case)
        character(len=*), intent(in) :: nx, ny
            !! cells per axis
        type(case_type), intent(out) :: case
            !! the case

        type(error_type), allocatable :: error

        call read_case_string('{"name": "slabs", "domain": {"nx": '//nx//', "ny": '//ny// &
            ', "dx": 0.5, "origin": [-1, 2], "boundaries": {"xmin": "fixed", "xmax": "fixed", '// &
            '"ymin": "sliding", "ymax": "sliding"}}, "particles": {"ppc": 2}, "materials": '// &
            '[{"name": "m", "type": "linear_elastic", "E": 1000, "nu": 0.2, "rho": 10}], '// &
            '"bodies": [{"material": "m", "min": [-1, 2], "max": [0, 3]}], "time": {"tend": 1}}', &
            case, error, "slabs")
        call check(suite, .not. allocated(error), "case "//nx//" x "//ny//" is valid")
        if (allocated(error)) print "(a)", error%message
    end subroutine grid_case

    !> The longest axis is cut; coordinates map to clamped cells.
    subroutine test_axis_and_cells()
        type(case_type) :: case

        call grid_case("12", "30", case)
        call check(suite, cut_axis(case) == 2, "the axis with the most cells is cut")
        call grid_case("20", "20", case)
        call check(suite, cut_axis(case) == 1, "the first of equal axes is cut")
        call check(suite, global_cell(case, -1.0_wp, 1) == 0, "cell of the origin: 0")
        call check(suite, global_cell(case, 0.74_wp, 1) == 3, "cell of x = 0.74: 3")
        call check(suite, global_cell(case, -5.0_wp, 1) == 0, "below the grid: clamped to 0")
        call check(suite, global_cell(case, 50.0_wp, 2) == 19, "above the grid: the last cell")
    end subroutine test_axis_and_cells

    !> The cuts put about the same number of particles on each image.
    subroutine test_balance()
        type(case_type) :: case
        type(decomposition_type) :: dec
        type(error_type), allocatable :: error
        integer(i8) :: histogram(0:29), share
        integer :: k
        logical :: slabs, balanced

        call grid_case("12", "30", case)
        ! particles in the low half only: 100 per layer in layers 0-14
        histogram = 0
        histogram(0:14) = 100
        call new_decomposition(dec, case, 3, 2, histogram, error)
        call check(suite, .not. allocated(error), "3 images on 30 layers: accepted")
        if (allocated(error)) return
        call check(suite, dec%axis == 2 .and. dec%cuts(0) == 0 .and. dec%cuts(3) == 30, &
            "the cuts span the axis")
        slabs = full_slabs(dec)
        balanced = .true.
        do k = 1, 2
            share = sum(histogram(dec%cuts(k - 1):dec%cuts(k) - 1))
            balanced = balanced .and. abs(share - 500_i8) <= 100_i8
        end do
        call check(suite, slabs, "every slab has min_slab_cells cells or more")
        call check(suite, balanced, "images 1 and 2 hold 500 particles each, within a layer")
        call check(suite, all(dec%cuts(0:3) == [0, 5, 10, 30]), "the cuts at layers 5 and 10")
        call check(suite, dec%me == 2 .and. dec%left == 1 .and. dec%right == 3 .and. &
            dec%cell_lo == 5 .and. dec%cell_hi == 10 .and. dec%node_lo == 4, &
            "image 2: slab 5-10, neighbours 1 and 3, first node layer 4 (a ghost cell)")
        ! all particles in one layer: the slabs still keep their cells
        histogram = 0
        histogram(29) = 1000
        call new_decomposition(dec, case, 4, 1, histogram, error)
        call check(suite, .not. allocated(error), "4 images, particles in the top layer")
        if (allocated(error)) return
        slabs = full_slabs(dec)
        call check(suite, slabs .and. dec%cuts(4) == 30, &
            "every slab keeps min_slab_cells cells when the particles are in one layer")
    end subroutine test_balance

    !> Whether every slab of dec has min_slab_cells cells or more.
    pure logical function full_slabs(dec)
        type(decomposition_type), intent(in) :: dec
            !! a decomposition with its cuts

        integer :: k

        full_slabs = .true.
        do k = 1, dec%images
            full_slabs = full_slabs .and. dec%cuts(k) - dec%cuts(k - 1) >= min_slab_cells
        end do
    end function full_slabs

    !> One image cuts nothing; no particles: equal slabs.
    subroutine test_uniform_and_empty()
        type(case_type) :: case
        type(decomposition_type) :: dec
        type(error_type), allocatable :: error
        integer(i8) :: histogram(0:29)

        call grid_case("12", "30", case)
        histogram = 7
        call new_decomposition(dec, case, 1, 1, histogram, error)
        call check(suite, .not. allocated(error) .and. dec%axis == 0 .and. dec%left == 0 .and. &
            dec%right == 0, "one image: nothing cut, no neighbours")
        histogram = 0
        call new_decomposition(dec, case, 3, 3, histogram, error)
        call check(suite, .not. allocated(error), "no particles: accepted")
        if (allocated(error)) return
        call check(suite, all(dec%cuts == [0, 10, 20, 30]), "no particles: equal slabs")
        call check(suite, dec%right == 0 .and. dec%left == 2 .and. dec%node_lo == 19, &
            "the last image: no right neighbour, a ghost cell below")
    end subroutine test_uniform_and_empty

    !> A grid with fewer than min_slab_cells cells per image is refused with its reason.
    subroutine test_too_few_cells()
        type(case_type) :: case
        type(decomposition_type) :: dec
        type(error_type), allocatable :: error
        integer(i8) :: histogram(0:29)

        call grid_case("12", "30", case)
        histogram = 1
        call new_decomposition(dec, case, 11, 1, histogram, error)
        call check(suite, allocated(error), "11 images on 30 cells: refused")
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_input, "refused as bad input")
        call check_contains(suite, error%message, "11 images need at least 33 cells along "// &
            "the longest axis (y, 30 cells", "the message gives the count, axis and cells")
        call new_decomposition(dec, case, 10, 1, histogram, error)
        call check(suite, .not. allocated(error), "10 images on 30 cells: accepted")
    end subroutine test_too_few_cells

    !> Each image's grid: its slab and ghost cells, free faces at the cuts only.
    subroutine test_local_grids()
        type(case_type) :: case, local
        type(decomposition_type) :: dec
        type(error_type), allocatable :: error
        integer(i8) :: histogram(0:29)
        real(wp), allocatable :: origins(:, :)
        integer, allocatable :: nns(:, :)

        call grid_case("12", "30", case)
        histogram = 0
        call new_decomposition(dec, case, 3, 2, histogram, error)
        if (allocated(error)) return
        local = local_case(case, dec)
        ! slab 10-20 with a ghost cell on each side: cells 9-21, origin 2 + 9 x 0.5
        call check(suite, local%domain%ncells(2) == 12 .and. local%domain%ncells(1) == 12, &
            "image 2: 10 cells and two ghost cells along y, all 12 along x")
        call check(suite, local%domain%origin(2) == 6.5_wp .and. local%domain%origin(1) == &
            -1.0_wp, "image 2: its origin at the first ghost layer")
        call check(suite, local%domain%face_text(1, 2) == "free" .and. &
            local%domain%face_text(2, 2) == "free", "image 2: both cuts are free faces")
        call check(suite, local%domain%face_text(1, 1) == "fixed", &
            "image 2: the faces along x stay as the case gives them")
        call image_grids(case, dec, origins, nns)
        call check(suite, all(nns(2, :) == [12, 13, 12]) .and. all(nns(1, :) == 13) .and. &
            all(nns(3, :) == 1), "image grids: node layers 0-11, 9-21, 19-30; 1 in z")
        call check(suite, all(origins(2, :) == [2.0_wp, 6.5_wp, 11.5_wp]), &
            "image grids: the origins of the slabs")
        call new_decomposition(dec, case, 3, 1, histogram, error)
        local = local_case(case, dec)
        call check(suite, local%domain%face_text(1, 2) == "sliding" .and. &
            local%domain%face_text(2, 2) == "free", &
            "image 1: the case's face below, a free cut above")
    end subroutine test_local_grids

end program test_mpm_decomposition
